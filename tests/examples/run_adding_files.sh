#!/usr/bin/env bash
# The worked examples of docs/adding-an-element.md and docs/laws.md ("Adding a law"),
# run as a newcomer would, in a scratch project: its elements/ holds tet4,
# quad4 and the element file printed in the first page (quad9), its laws/
# hooke, stvk and the law file printed in the second (mooney_rivlin). The
# generator makes that project's registry; the scratch kernels are compiled
# and linked, in place of the build's own, into the CLI and into the kernel
# test suite (link commands from the Ninja build tree); the CLI then makes a
# quad9 beam and runs a Mooney-Rivlin scene on it, and the kernel suite runs
# on the scratch registry. Nothing of the source tree is touched.
# usage: run_adding_files.sh SOURCE_DIR BUILD_DIR PYTHON [NINJA]
set -euo pipefail
source_dir=$(cd "$1" && pwd)
build_dir=$(cd "$2" && pwd)
python=$3
ninja=${4:-ninja}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
project=$work/project
mkdir -p "$project/elements" "$project/laws"
cp -r "$source_dir/generator" "$source_dir/templates" "$project/"
rm -rf "$project/generator/__pycache__"

# The code block that follows "<!-- file: NAME -->" in a doc page.
extract() {
  awk -v name="$2" '
    $0 == "<!-- file: " name " -->" { found = 1; next }
    found && /^```/ { if (inside) exit; inside = 1; next }
    inside { print }' "$1"
}
cp "$source_dir"/elements/{tet4,quad4}.toml "$project/elements/"
cp "$source_dir"/laws/{hooke,stvk}.toml "$project/laws/"
extract "$source_dir/docs/adding-an-element.md" elements/quad9.toml > "$project/elements/quad9.toml"
extract "$source_dir/docs/laws.md" laws/mooney_rivlin.toml > "$project/laws/mooney_rivlin.toml"
# The pages print the shipped files, so that neither can drift from the other.
cmp "$project/elements/quad9.toml" "$source_dir/elements/quad9.toml"
cmp "$project/laws/mooney_rivlin.toml" "$source_dir/laws/mooney_rivlin.toml"

# Generate, then compile what tensormass_kernels compiles (no terms split).
(cd "$project" && "$python" -m generator --verbose | tail -1)
flags=(-std=c++20 -O1 -march=native -fopenmp-simd -fno-math-errno -DTENSORMASS_SIMD=1 -DTENSORMASS_VECTOR_MATH=1
       -I"$source_dir/runtime/include")
mkdir -p "$work/objects"
sources=("$project"/generated/registry.cpp "$project"/generated/elements.cpp
         "$source_dir"/runtime/src/kernels/registry.cpp "$source_dir"/runtime/src/kernels/law_parameters.cpp)
for kernel in "$project"/generated/kernels/*.cpp; do
  case $kernel in *_terms*) ;; *) sources+=("$kernel") ;; esac
done
for file in "${sources[@]}"; do
  c++ "${flags[@]}" -c "$file" -o "$work/objects/$(basename "$(dirname "$file")")_$(basename "$file").o" &
  while [ "$(jobs -r | wc -l)" -ge "$(nproc)" ]; do wait -n; done
done
wait
ar rcs "$work/libscratch_kernels.a" "$work"/objects/*.o

# Relink a build target with the scratch kernels instead of the build's.
relink() {
  local command
  command=$("$ninja" -C "$build_dir" -t commands "$1" | tail -1)
  case $command in *runtime/libtensormass_kernels.a*) ;; *) echo "no kernel library in the link of $1" >&2; exit 1 ;; esac
  command=${command//runtime\/libtensormass_kernels.a/$work\/libscratch_kernels.a}
  command=${command/-o $1 /-o $work/$(basename "$1") }
  (cd "$build_dir" && eval "$command")
}
relink tensormass
relink tests/kernels/tensormass_kernel_tests

"$work/tensormass" kernels | grep -q "^18 kernels" || { "$work/tensormass" kernels; exit 1; }  # 9 whole, 4 tensor, 3 fbar (quad4), 2 anp (tet4)
"$work/tensormass" kernels | grep -q "mooney_rivlin quad9"
cd "$work"
./tensormass beam --type quad9 --cells 12,2 -o beam.msh > /dev/null
sed 's/out-mooney-rivlin/out/' "$source_dir/examples/beam/mooney_rivlin.yaml" > scene.yaml
./tensormass run scene.yaml --quiet
grep -q '"status": "ok"' out/summary.json
# A constant the law does not have is refused before anything runs.
sed 's/c01: /c02: /' scene.yaml > bad.yaml
if ./tensormass run bad.yaml --quiet 2> error.txt; then echo "a scene with c02 ran" >&2; exit 1; fi
grep -q "c02" error.txt || { cat error.txt; exit 1; }
TENSORMASS_INPUTS_DIR="$project" ./tensormass_kernel_tests --gtest_brief=1
echo "the worked examples of adding an element and a law ran"

# Sanitizer and fuzzer builds (docs/sanitizers-and-fuzzing.md), included by
# the top-level CMakeLists.txt before any target is defined.
#   TENSORMASS_SANITIZE        every target compiled and linked with ASan + UBSan
#   TENSORMASS_BUILD_FUZZERS   the same plus libFuzzer coverage (clang only),
#                              and the fuzz/ targets
# Undefined behaviour aborts (-fno-sanitize-recover) so that a test or a
# fuzzer fails on it instead of printing a line nobody reads.
set(TENSORMASS_SANITIZER_FLAGS -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)

if(TENSORMASS_BUILD_FUZZERS)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "TENSORMASS_BUILD_FUZZERS needs clang (libFuzzer): configure with -DCMAKE_CXX_COMPILER=clang++ "
                        "-DCMAKE_C_COMPILER=clang (scripts/run-fuzzers.sh does)")
  endif()
  # fuzzer-no-link: coverage feedback in every library; only the fuzz
  # executables link libFuzzer's main (fuzz/CMakeLists.txt).
  list(APPEND TENSORMASS_SANITIZER_FLAGS -fsanitize=fuzzer-no-link)
  # The project's warning flags are GCC's (-Wno-restrict): clang need not say so 230 times.
  add_compile_options(-Wno-unknown-warning-option)
endif()

if(TENSORMASS_SANITIZE OR TENSORMASS_BUILD_FUZZERS)
  add_compile_options(${TENSORMASS_SANITIZER_FLAGS})
  add_link_options(${TENSORMASS_SANITIZER_FLAGS})
endif()

# tensormass_sanitizer_kernel_exceptions(): called once the kernels target
# exists. The generated kernels are long straight-line functions of pointer
# arithmetic; two clang-only costs are avoided there:
# - in a fuzzer build no reader calls a kernel, so the kernels are left
#   uninstrumented (instrumenting them would double the build for no finding);
# - in a clang sanitizer build, UBSan's pointer-overflow, alignment and null
#   checks make clang 14 -O1 take over 19 minutes on the largest kernel
#   (corotational_hex20_terms_part0.cpp, 8 s without them); ASan and the other
#   UBSan checks stay. GCC has no such blow-up and keeps every check.
function(tensormass_sanitizer_kernel_exceptions)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    return()
  endif()
  if(TENSORMASS_BUILD_FUZZERS)
    # -w: what clang says of generated code is not what this build looks for.
    set(exception -fno-sanitize=all -w)
  elseif(TENSORMASS_SANITIZE)
    set(exception -fno-sanitize=pointer-overflow,alignment,null)
  else()
    return()
  endif()
  set(kernels ${TENSORMASS_GENERATED_SOURCES})
  list(FILTER kernels INCLUDE REGEX "^kernels/")
  list(TRANSFORM kernels PREPEND ${TENSORMASS_GENERATED_DIR}/)
  set_source_files_properties(${kernels} DIRECTORY ${PROJECT_SOURCE_DIR}/runtime PROPERTIES COMPILE_OPTIONS "${exception}")
endfunction()

// Checkpoints: a little-endian binary file, "tensormass checkpoint", a
// version, the payload's size and its XXH3-64 checksum, then the payload:
// the fields in a fixed order, each array preceded by its length.
// Fingerprints are FNV-1a over the bytes of what they cover.
#include "tensormass/simulation/checkpoint.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <regex>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "common/checksum.hpp"
#include "common/regular_file.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/io/atomic_file.hpp"
#include "tensormass/kernels/registry.hpp"

namespace tensormass {

namespace {

constexpr char kMagic[] = "tensormass checkpoint";
// 5: the payload's size and checksum in the header; 6: step series; 7: track
// files and adaptivity records streamed, their marks kept
constexpr std::uint64_t kVersion = 8;

/// FNV-1a, 64 bits.
class Fingerprint {
 public:
  void bytes(const void* data, std::size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) hash_ = (hash_ ^ p[i]) * 1099511628211ull;
  }
  template <class T>
  void add(const T& value) {
    static_assert(std::is_arithmetic_v<T>);
    bytes(&value, sizeof value);
  }
  void add(const std::string& text) {
    add(text.size());
    bytes(text.data(), text.size());
  }
  template <class T>
  void add(const std::vector<T>& values) {
    add(values.size());
    for (const T& v : values) add(v);
  }
  template <class T, std::size_t N>
  void add(const std::array<T, N>& values) {
    for (const T& v : values) add(v);
  }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 14695981039346656037ull;
};

void add_profile(Fingerprint& f, const TimeProfile& p) {
  f.add(static_cast<int>(p.kind));
  f.add(p.duration);
  f.add(p.period);
  f.add(p.phase);
}

void add_model(Fingerprint& f, const ModelSpec& model) {
  for (const MaterialSpec& m : model.materials) {
    f.add(m.region), f.add(m.law), f.add(m.split);
    for (const auto& [name, value] : m.constants) f.add(name), f.add(value);
    f.add(m.density);
  }
  f.add(model.fixed);
  for (const PrescribedSpec& p : model.prescribed) {
    f.add(p.region), f.add(p.displacement);
    for (bool c : p.components) f.add(c);
    add_profile(f, p.profile);
    f.add(p.rotates), f.add(p.rotation.axis), f.add(p.rotation.centre), f.add(p.rotation.angle);
  }
  f.add(model.loads.gravity);
  for (const NodalForceSpec& l : model.loads.nodal_forces) f.add(l.region), f.add(l.force);
  for (const PressureSpec& l : model.loads.pressures) f.add(l.region), f.add(l.pressure);
  add_profile(f, model.loads.profile);
}

void add_solver(Fingerprint& f, const SolverSettings& s) {
  f.add(static_cast<int>(s.type));
  f.add(s.load_steps), f.add(s.tolerance), f.add(s.max_iterations), f.add(s.dt);
  if (s.is_static()) f.add(s.steps);
  f.add(s.newton_iterations), f.add(s.damping_mass), f.add(s.damping_stiffness);
  f.add(static_cast<int>(s.predictor)), f.add(s.project_hessian);
  f.add(static_cast<int>(s.linear.type)), f.add(s.linear.tolerance), f.add(s.linear.max_iterations);
  f.add(s.linear.reuse_iterations);
}

// --- Binary writing and reading ----------------------------------------------------

/// Writes values to a stream, and the checksum and size of what it wrote.
class Writer {
 public:
  explicit Writer(std::ostream& out) : out_(out) {}
  template <class T>
  void put(const T& value) {
    static_assert(std::is_arithmetic_v<T>);
    write(&value, sizeof value);
  }
  template <class T>
  void put(const std::vector<T>& values) {
    put(static_cast<std::uint64_t>(values.size()));
    if (!values.empty()) write(values.data(), sizeof(T) * values.size());
  }
  void put(const std::string& text) {
    put(static_cast<std::uint64_t>(text.size()));
    write(text.data(), text.size());
  }
  std::uint64_t size() const { return size_; }
  std::uint64_t checksum() const { return hash_.value(); }

 private:
  void write(const void* data, std::size_t size) {
    out_.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
    hash_.update(data, size);
    size_ += size;
  }
  std::ostream& out_;
  detail::Checksum hash_;
  std::uint64_t size_ = 0;
};

/// The header before the payload: the magic text and the version.
void put_header(std::ostream& out) {
  const std::uint64_t magic_size = sizeof kMagic - 1;
  out.write(reinterpret_cast<const char*>(&magic_size), sizeof magic_size);
  out.write(kMagic, static_cast<std::streamsize>(magic_size));
  out.write(reinterpret_cast<const char*>(&kVersion), sizeof kVersion);
}

class Reader {
 public:
  Reader(std::string bytes, std::string path) : bytes_(std::move(bytes)), path_(std::move(path)) {}
  template <class T>
  T get() {
    static_assert(std::is_arithmetic_v<T>);
    T value;
    std::memcpy(&value, take(sizeof value), sizeof value);
    return value;
  }
  template <class T>
  std::vector<T> get_vector() {
    const std::uint64_t count = get<std::uint64_t>();
    if (count > (bytes_.size() - at_) / sizeof(T)) fail("an array runs past the end of the file");
    std::vector<T> values(count);
    if (count) std::memcpy(values.data(), take(sizeof(T) * count), sizeof(T) * count);
    return values;
  }
  std::string get_string() {
    const std::uint64_t count = get<std::uint64_t>();
    if (count > bytes_.size() - at_) fail("a string runs past the end of the file");
    return std::string(take(count), count);
  }
  /// A count of items of at least `bytes_each` bytes each, refused when
  /// they cannot fit in the bytes left (nothing is allocated for them).
  std::uint64_t get_count(std::size_t bytes_each) {
    const std::uint64_t count = get<std::uint64_t>();
    if (count > (bytes_.size() - at_) / bytes_each) fail("a count runs past the end of the file");
    return count;
  }
  bool at_end() const { return at_ == bytes_.size(); }
  std::size_t left() const { return bytes_.size() - at_; }
  const char* here() const { return bytes_.data() + at_; }
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError("checkpoint " + path_ + ": " + what + " (truncated or not a tensormass checkpoint)");
  }

 private:
  const char* take(std::size_t size) {
    if (size > bytes_.size() - at_) fail("it ends early");
    const char* p = bytes_.data() + at_;
    at_ += size;
    return p;
  }
  std::string bytes_;
  std::string path_;
  std::size_t at_ = 0;
};

void put_state(Writer& w, const State& s) {
  w.put(s.time), w.put(static_cast<std::int64_t>(s.step));
  w.put(s.displacement), w.put(s.velocity), w.put(s.warm_start);
  w.put(s.previous_displacement), w.put(s.earlier_displacement), w.put(s.viscous_history);
}

State get_state(Reader& r) {
  State s;
  s.time = r.get<double>();
  s.step = static_cast<int>(r.get<std::int64_t>());
  s.displacement = r.get_vector<double>();
  s.velocity = r.get_vector<double>();
  s.warm_start = r.get_vector<double>();
  s.previous_displacement = r.get_vector<double>();
  s.earlier_displacement = r.get_vector<double>();
  s.viscous_history = r.get_vector<double>();
  return s;
}

template <class T>
void put_series(Writer& w, const StepSeries<T>& series) {
  const typename StepSeries<T>::Saved saved = series.saved();
  w.put(saved.listed), w.put(saved.count), w.put(saved.sum), w.put(saved.bins);
  w.put(saved.last), w.put(static_cast<std::int64_t>(saved.can_take_back));
}

template <class T>
StepSeries<T> get_series(Reader& r) {
  typename StepSeries<T>::Saved saved;
  saved.listed = r.get_vector<T>();
  saved.count = r.get<std::uint64_t>();
  saved.sum = r.get<double>();
  saved.bins = r.get_vector<std::uint64_t>();
  saved.last = r.get<T>();
  saved.can_take_back = r.get<std::int64_t>() != 0;
  try {
    return StepSeries<T>(std::move(saved));
  } catch (const std::invalid_argument&) {
    r.fail("inconsistent per-step series");
  }
}

void put_statistics(Writer& w, const SolveStatistics& s) {
  w.put(s.assembly_seconds), w.put(s.solve_seconds), w.put(s.stable_dt);
  w.put(static_cast<std::int64_t>(s.newton_iterations)), w.put(static_cast<std::int64_t>(s.shortened_steps));
  w.put(static_cast<std::int64_t>(s.linear_iterations)), w.put(static_cast<std::int64_t>(s.factorizations));
  put_series(w, s.newton_per_step), put_series(w, s.step_ms);
}

SolveStatistics get_statistics(Reader& r) {
  SolveStatistics s;
  s.assembly_seconds = r.get<double>();
  s.solve_seconds = r.get<double>();
  s.stable_dt = r.get<double>();
  s.newton_iterations = static_cast<int>(r.get<std::int64_t>());
  s.shortened_steps = static_cast<int>(r.get<std::int64_t>());
  s.linear_iterations = r.get<std::int64_t>();
  s.factorizations = static_cast<int>(r.get<std::int64_t>());
  s.newton_per_step = get_series<int>(r);
  s.step_ms = get_series<double>(r);
  return s;
}

std::string kernel_name(const tm_kernel& kernel) { return std::string(kernel.law) + "/" + kernel.split; }

/// Index of `kernel` in the table, added when new; -1 for nullptr.
int kernel_index(std::vector<std::string>& table, const tm_kernel* kernel) {
  if (!kernel) return -1;
  const std::string name = kernel_name(*kernel);
  const auto found = std::find(table.begin(), table.end(), name);
  if (found != table.end()) return static_cast<int>(found - table.begin());
  table.push_back(name);
  return static_cast<int>(table.size()) - 1;
}

/// The registry's kernel named table[index] for the cell's element (nullptr for -1).
const tm_kernel* saved_kernel(const SavedLaws& saved, int index, const Model& model, int cell) {
  if (index < 0) return nullptr;
  if (index >= static_cast<int>(saved.kernels.size())) throw InputError("checkpoint: a kernel index is out of range");
  const std::string& name = saved.kernels[index];
  const std::size_t slash = name.find('/');
  const tm_kernel* kernel = Registry::instance().find(name.substr(0, slash), model.kernel(cell).element,
                                                      slash == std::string::npos ? "" : name.substr(slash + 1));
  if (!kernel)
    throw InputError("checkpoint: no kernel " + name + " for " + model.mesh().describe_cell(cell) +
                     " in this build's registry");
  return kernel;
}

void put_records(Writer& w, const std::vector<AdaptivityRecord>& records) {
  w.put(static_cast<std::uint64_t>(records.size()));
  for (const AdaptivityRecord& r : records) {
    w.put(static_cast<std::int64_t>(r.step)), w.put(static_cast<std::int64_t>(r.upgrades));
    w.put(static_cast<std::int64_t>(r.downgrades)), w.put(static_cast<std::uint64_t>(r.cells_per_law.size()));
    for (const auto& [law, count] : r.cells_per_law) w.put(law), w.put(static_cast<std::int64_t>(count));
  }
}

std::vector<AdaptivityRecord> get_records(Reader& r) {
  std::vector<AdaptivityRecord> records;
  const auto count = r.get_count(4 * sizeof(std::int64_t));
  for (std::uint64_t i = 0; i < count; ++i) {
    AdaptivityRecord record;
    record.step = static_cast<int>(r.get<std::int64_t>());
    record.upgrades = static_cast<int>(r.get<std::int64_t>());
    record.downgrades = static_cast<int>(r.get<std::int64_t>());
    const auto laws = r.get_count(2 * sizeof(std::int64_t));
    for (std::uint64_t k = 0; k < laws; ++k) {
      std::string law = r.get_string();
      record.cells_per_law.emplace_back(std::move(law), static_cast<int>(r.get<std::int64_t>()));
    }
    records.push_back(std::move(record));
  }
  return records;
}

void put_mark(Writer& w, const io::StreamMark& m) { w.put(m.rows), w.put(m.bytes), w.put(m.checksum); }

io::StreamMark get_mark(Reader& r) {
  io::StreamMark m;
  m.rows = r.get<std::uint64_t>();
  m.bytes = r.get<std::uint64_t>();
  m.checksum = r.get<std::uint64_t>();
  return m;
}

void put_laws(Writer& w, const SavedLaws& l) {
  w.put(static_cast<std::uint64_t>(l.kernels.size()));
  for (const std::string& name : l.kernels) w.put(name);
  w.put(l.current), w.put(l.blend_from), w.put(l.blend_weight);
  w.put(static_cast<std::int64_t>(l.folding));
  w.put(l.folded), w.put(l.folded_blocks);
  w.put(static_cast<std::int64_t>(l.folded_count)), w.put(static_cast<std::int64_t>(l.folding_changes));
  w.put(static_cast<std::int64_t>(l.constants_changed));
  const AdaptivityMemory& a = l.adaptivity;
  w.put(a.calm_evaluations);
  w.put(static_cast<std::uint64_t>(a.values.size()));
  for (const auto& v : a.values) w.put(v);
  w.put(static_cast<std::int64_t>(a.total_switches)), w.put(a.criteria_seconds), w.put(a.criterion_seconds);
  put_records(w, a.records.listed);
  put_records(w, a.records.switching);
  w.put(static_cast<std::int64_t>(a.records.evaluations));
  w.put(static_cast<std::int64_t>(a.records.switching_evaluations));
  put_records(w, {a.last_record});
}

SavedLaws get_laws(Reader& r) {
  SavedLaws l;
  const auto kernels = r.get_count(sizeof(std::uint64_t));
  for (std::uint64_t k = 0; k < kernels; ++k) l.kernels.push_back(r.get_string());
  l.current = r.get_vector<int>();
  l.blend_from = r.get_vector<int>();
  l.blend_weight = r.get_vector<double>();
  l.folding = r.get<std::int64_t>() != 0;
  l.folded = r.get_vector<int>();
  l.folded_blocks = r.get_vector<double>();
  l.folded_count = static_cast<int>(r.get<std::int64_t>());
  l.folding_changes = r.get<std::int64_t>();
  l.constants_changed = r.get<std::int64_t>() != 0;
  AdaptivityMemory& a = l.adaptivity;
  a.calm_evaluations = r.get_vector<int>();
  const auto criteria = r.get_count(sizeof(std::uint64_t));
  for (std::uint64_t c = 0; c < criteria; ++c) a.values.push_back(r.get_vector<double>());
  a.total_switches = static_cast<int>(r.get<std::int64_t>());
  a.criteria_seconds = r.get<double>();
  a.criterion_seconds = r.get_vector<double>();
  a.records.listed = get_records(r);
  a.records.switching = get_records(r);
  a.records.evaluations = r.get<std::int64_t>();
  a.records.switching_evaluations = r.get<std::int64_t>();
  const std::vector<AdaptivityRecord> last = get_records(r);
  if (last.size() != 1) r.fail("no last adaptivity record");
  a.last_record = last.front();
  return l;
}

bool finite(const std::vector<double>& values) {
  return std::all_of(values.begin(), values.end(), [](double x) { return std::isfinite(x); });
}

/// The fields a checkpoint holds whatever the run: InputError naming the
/// field when one is out of what a run writes.
void check_fields(const Checkpoint& c, const std::string& path) {
  const auto refuse = [&](const std::string& field, const std::string& what) {
    throw InputError("checkpoint " + path + ": " + field + " " + what +
                     " (damaged or forged; remove it to start afresh)");
  };
  const State& s = c.state;
  if (s.step < 0) refuse("state.step", "is negative (" + std::to_string(s.step) + ")");
  if (!std::isfinite(s.time) || s.time < 0) refuse("state.time", "is not a finite time >= 0");
  for (const auto& [name, values] : {std::pair{"state.displacement", &s.displacement},
                                     {"state.velocity", &s.velocity},
                                     {"state.warm_start", &s.warm_start},
                                     {"state.previous_displacement", &s.previous_displacement},
                                     {"state.earlier_displacement", &s.earlier_displacement},
                                     {"state.viscous_history", &s.viscous_history}})
    if (!finite(*values)) refuse(name, "holds a value that is not finite");
  static const std::regex frame_name("frame_[0-9]{6,9}\\.p?vtu");  // a step fits an int
  double previous = -1.0;
  for (const io::SeriesEntry& e : c.series) {
    if (!std::regex_match(e.file, frame_name)) refuse("series", "names a file a run does not write");
    if (!std::isfinite(e.time) || e.time < previous) refuse("series", "has times out of order");
    previous = e.time;
  }
  if (c.series.size() > static_cast<std::size_t>(s.step) + 1) refuse("series", "has more frames than steps");
  for (const SavedTrack& t : c.tracks) {
    if (!finite({t.first_shift.begin(), t.first_shift.end()})) refuse("tracks", "hold a value that is not finite");
    if (t.file.rows == 0 || t.file.rows > static_cast<std::uint64_t>(s.step) + 1 || t.file.bytes < t.file.rows)
      refuse("tracks", "mark more rows than the steps recorded, or none");
  }
  if (c.adaptive && c.adaptivity_records.rows != static_cast<std::uint64_t>(c.laws.adaptivity.records.evaluations))
    refuse("adaptivity records", "mark another count of evaluations than the adaptive model's");
}

}  // namespace

SavedLaws save_laws(const Model& model, const Assembler& assembler, const Adaptivity& adaptivity) {
  SavedLaws l;
  const int cells = model.cell_count();
  for (int cell = 0; cell < cells; ++cell) {
    l.current.push_back(kernel_index(l.kernels, &model.kernel(cell)));
    l.blend_from.push_back(kernel_index(l.kernels, model.blend_from(cell)));
    l.blend_weight.push_back(model.blend_weight(cell));
  }
  if (const LinearPart* part = assembler.linear_part()) {
    LinearPart::Saved folded = part->saved();
    l.folding = true;
    for (const tm_kernel* kernel : folded.folded) l.folded.push_back(kernel_index(l.kernels, kernel));
    l.folded_blocks = std::move(folded.blocks);
    l.folded_count = folded.folded_count;
    l.folding_changes = folded.changes;
    l.constants_changed = folded.constants_changed;
  }
  l.adaptivity = adaptivity.memory();
  return l;
}

void restore_laws(const SavedLaws& l, Model& model, const Assembler& assembler, Adaptivity& adaptivity) {
  const int cells = model.cell_count();
  if (static_cast<int>(l.current.size()) != cells || l.blend_from.size() != l.current.size() ||
      l.blend_weight.size() != l.current.size())
    throw InputError("checkpoint: its laws are for " + std::to_string(l.current.size()) + " cells, the model has " +
                     std::to_string(cells));
  for (int cell = 0; cell < cells; ++cell) {
    const tm_kernel* kernel = saved_kernel(l, l.current[cell], model, cell);
    model.set_law(cell, kernel->law);
    if (&model.kernel(cell) != kernel)
      throw InputError("checkpoint: " + model.mesh().describe_cell(cell) + " cannot take kernel " +
                       kernel_name(*kernel) + " back (another split)");
    if (const tm_kernel* from = saved_kernel(l, l.blend_from[cell], model, cell)) {
      model.start_blend(cell, from);
      model.set_blend_weight(cell, l.blend_weight[cell]);
    }
  }
  LinearPart* part = assembler.linear_part();
  if (part && l.folding) {
    LinearPart::Saved folded{l.folded_blocks, {}, l.folded_count, l.folding_changes, l.constants_changed};
    if (static_cast<int>(l.folded.size()) != cells) throw InputError("checkpoint: its folded cells do not fit");
    for (int cell = 0; cell < cells; ++cell) folded.folded.push_back(saved_kernel(l, l.folded[cell], model, cell));
    try {
      part->restore(std::move(folded));
    } catch (const std::invalid_argument& e) {
      throw InputError(std::string("checkpoint: ") + e.what());
    }
  }
  try {
    adaptivity.restore(l.adaptivity);
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("checkpoint: ") + e.what());
  }
}

void put_refinement(Writer& w, const SavedRefinement& s) {
  w.put(s.coarsens), w.put(s.max_levels), w.put(s.offsets), w.put(s.cells), w.put(s.calm), w.put(s.peak);
  w.put(s.event_steps), w.put(s.event_cells), w.put(s.event_level_offsets), w.put(s.event_levels);
}

SavedRefinement get_refinement(Reader& r) {
  SavedRefinement s;
  s.coarsens = r.get_vector<int>();
  s.max_levels = r.get_vector<int>();
  s.offsets = r.get_vector<int>();
  s.cells = r.get_vector<int>();
  s.calm = r.get_vector<int>();
  s.peak = r.get<double>();
  s.event_steps = r.get_vector<int>();
  s.event_cells = r.get_vector<int>();
  s.event_level_offsets = r.get_vector<int>();
  s.event_levels = r.get_vector<int>();
  const std::size_t operations = s.coarsens.size();
  if (s.max_levels.size() != operations || s.offsets.size() != operations + 1 || s.offsets.front() != 0 ||
      static_cast<std::size_t>(s.offsets.back()) != s.cells.size() ||
      !std::is_sorted(s.offsets.begin(), s.offsets.end()) || s.event_cells.size() != s.event_steps.size() ||
      s.event_level_offsets.size() != s.event_steps.size() + 1 || s.event_level_offsets.front() != 0 ||
      static_cast<std::size_t>(s.event_level_offsets.back()) != s.event_levels.size() ||
      !std::is_sorted(s.event_level_offsets.begin(), s.event_level_offsets.end()))
    r.fail("inconsistent refinement history");
  return s;
}

std::uint64_t mesh_fingerprint(const Mesh& mesh) {
  Fingerprint f;
  f.add(mesh.dim);
  f.add(mesh.rest_positions);
  for (const ElementBlock& block : mesh.blocks) f.add(std::string(block.element->name)), f.add(block.connectivity);
  for (const Group& group : mesh.groups) f.add(group.name), f.add(group.nodes), f.add(group.cells);
  return f.value();
}

std::uint64_t scene_fingerprint(const Scene& scene) {
  Fingerprint f;
  add_model(f, scene.model);
  add_solver(f, scene.solver);
  const AdaptivitySettings& a = scene.adaptivity;
  f.add(a.enabled);
  if (a.enabled) {
    for (const CriterionSpec& c : a.criteria) f.add(c.name), f.add(c.threshold), f.add(c.rung);
    f.add(a.ladder), f.add(static_cast<int>(a.action)), f.add(a.every), f.add(a.blend_steps);
    f.add(a.downgrade), f.add(a.hysteresis), f.add(a.calm_steps);
  }
  const RefinementSettings& refine = scene.refinement;
  f.add(refine.enabled);
  if (refine.enabled) {
    f.add(refine.threshold), f.add(refine.max_level), f.add(refine.every), f.add(refine.coarsen);
    f.add(refine.hysteresis), f.add(refine.calm_steps);
  }
  f.add(scene.output.every), f.add(scene.output.track);
  return f.value();
}

void write_checkpoint(const std::string& path, const Checkpoint& c) {
  io::write_atomically(
      path,
      [&](std::ostream& out) {
        put_header(out);
        const std::streampos sealed_at = out.tellp();
        const std::uint64_t seal[2] = {0, 0};  // the payload's size and checksum, once written
        out.write(reinterpret_cast<const char*>(seal), sizeof seal);
        Writer w(out);
        w.put(c.mesh_fingerprint), w.put(c.scene_fingerprint);
        put_state(w, c.state);
        w.put(c.linear_solver);
        put_statistics(w, c.statistics);
        put_series(w, c.step_assembly_ms), put_series(w, c.step_solve_ms), put_series(w, c.step_criteria_ms);
        w.put(static_cast<std::uint64_t>(c.tracks.size()));
        for (const SavedTrack& t : c.tracks) {
          put_mark(w, t.file);
          for (double x : t.first_shift) w.put(x);
        }
        w.put(static_cast<std::uint64_t>(c.series.size()));
        for (const io::SeriesEntry& e : c.series) w.put(e.time), w.put(e.file);
        w.put(static_cast<std::int64_t>(c.adaptive));
        if (c.adaptive) put_laws(w, c.laws), put_mark(w, c.adaptivity_records);
        w.put(static_cast<std::int64_t>(c.refining));
        if (c.refining) put_refinement(w, c.refinement);
        const std::uint64_t written[2] = {w.size(), w.checksum()};
        out.seekp(sealed_at);
        out.write(reinterpret_cast<const char*>(written), sizeof written);
        out.seekp(0, std::ios::end);
      },
      /*durable=*/true);
}

Checkpoint read_checkpoint(const std::string& path) {
  Reader r(detail::read_regular_file(path, "checkpoint"), path);
  if (r.get_string() != kMagic) r.fail("no checkpoint header");
  const auto version = r.get<std::uint64_t>();
  if (version != kVersion)
    throw InputError("checkpoint " + path + " has version " + std::to_string(version) + "; this tensormass reads " +
                     std::to_string(kVersion));
  const auto size = r.get<std::uint64_t>();
  const auto checksum = r.get<std::uint64_t>();
  if (size != r.left())
    throw InputError("checkpoint " + path + " holds " + std::to_string(r.left()) + " bytes after its header, not the " +
                     std::to_string(size) + " it was written with (truncated or damaged; remove it to start afresh)");
  if (detail::checksum(r.here(), r.left()) != checksum)
    throw InputError("checkpoint " + path +
                     ": its checksum does not match its contents (damaged or edited; remove it to start afresh)");
  Checkpoint c;
  c.mesh_fingerprint = r.get<std::uint64_t>();
  c.scene_fingerprint = r.get<std::uint64_t>();
  c.state = get_state(r);
  c.linear_solver = r.get_vector<double>();
  c.statistics = get_statistics(r);
  c.step_assembly_ms = get_series<double>(r);
  c.step_solve_ms = get_series<double>(r);
  c.step_criteria_ms = get_series<double>(r);
  const auto tracks = r.get_count(6 * sizeof(double));
  for (std::uint64_t t = 0; t < tracks; ++t) {
    SavedTrack track;
    track.file = get_mark(r);
    for (double& x : track.first_shift) x = r.get<double>();
    c.tracks.push_back(std::move(track));
  }
  const auto frames = r.get_count(2 * sizeof(double));
  for (std::uint64_t i = 0; i < frames; ++i) {
    const double time = r.get<double>();
    c.series.push_back({time, r.get_string()});
  }
  c.adaptive = r.get<std::int64_t>() != 0;
  if (c.adaptive) c.laws = get_laws(r), c.adaptivity_records = get_mark(r);
  c.refining = r.get<std::int64_t>() != 0;
  if (c.refining) c.refinement = get_refinement(r);
  if (!r.at_end()) r.fail("bytes after the last field");
  check_fields(c, path);
  return c;
}

}  // namespace tensormass

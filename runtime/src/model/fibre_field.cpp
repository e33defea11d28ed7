#include "tensormass/model/fibre_field.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "common/input_cursor.hpp"
#include "common/regular_file.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass {

namespace {

std::string point_text(const FibreField::Vector& x) {
  std::ostringstream out;
  out.precision(9);
  out << "(" << x[0] << ", " << x[1] << ", " << x[2] << ")";
  return out.str();
}

bool usable(const FibreField::Vector& a) {
  const double norm2 = a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
  return std::isfinite(norm2) && norm2 > 0.0;
}

/// The fields of one line split at commas, spaces and tabs.
std::vector<std::string_view> fields(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  for (std::size_t i = 0; i <= line.size(); ++i) {
    if (i < line.size() && line[i] != ',' && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') continue;
    if (i > start) out.push_back(line.substr(start, i - start));
    start = i + 1;
  }
  return out;
}

}  // namespace

/// Samples in a k-d tree: nodes are the samples themselves, ordered so that
/// the median of each range splits it along the axis depth % 3.
struct FibreField::SampleTree {
  std::vector<Vector> points;
  std::vector<Vector> directions;

  void build(std::vector<int>& order, int begin, int end, int depth) {
    if (end - begin <= 1) return;
    const int middle = (begin + end) / 2;
    const int axis = depth % 3;
    std::nth_element(order.begin() + begin, order.begin() + middle, order.begin() + end,
                     [&](int a, int b) { return points[a][axis] < points[b][axis]; });
    build(order, begin, middle, depth + 1);
    build(order, middle + 1, end, depth + 1);
  }

  void nearest(const Vector& x, int begin, int end, int depth, int& best, double& best_distance) const {
    if (begin >= end) return;
    const int middle = (begin + end) / 2;
    const Vector& p = points[middle];
    const double d = (p[0] - x[0]) * (p[0] - x[0]) + (p[1] - x[1]) * (p[1] - x[1]) + (p[2] - x[2]) * (p[2] - x[2]);
    if (d < best_distance || (d == best_distance && middle < best)) {
      best = middle;
      best_distance = d;
    }
    const double offset = x[depth % 3] - p[depth % 3];
    const bool left_first = offset < 0;
    nearest(x, left_first ? begin : middle + 1, left_first ? middle : end, depth + 1, best, best_distance);
    if (offset * offset <= best_distance)
      nearest(x, left_first ? middle + 1 : begin, left_first ? end : middle, depth + 1, best, best_distance);
  }

  /// Reorders the samples into tree order.
  void index() {
    std::vector<int> order(points.size());
    std::iota(order.begin(), order.end(), 0);
    build(order, 0, static_cast<int>(order.size()), 0);
    std::vector<Vector> p, a;
    for (const int i : order) {
      p.push_back(points[i]);
      a.push_back(directions[i]);
    }
    points = std::move(p);
    directions = std::move(a);
  }
};

FibreField FibreField::constant(const Vector& direction, std::string owner) {
  FibreField field;
  field.kind_ = Kind::constant;
  field.direction_ = direction;
  field.owner_ = std::move(owner);
  if (!usable(direction)) throw InputError(field.owner_ + ": the fibre direction must be a non-zero vector");
  return field;
}

FibreField FibreField::formula(const std::array<std::string, 3>& components, std::string owner) {
  FibreField field;
  field.kind_ = Kind::formula;
  field.owner_ = std::move(owner);
  for (int c = 0; c < 3; ++c) field.components_[c] = Expression(components[c], {"x", "y", "z"}, field.owner_);
  return field;
}

FibreField FibreField::samples(const std::string& path, std::string owner) {
  FibreField field;
  field.kind_ = Kind::samples;
  field.owner_ = std::move(owner);
  field.path_ = path;
  const std::string text = detail::read_regular_file(path, "fibre file");
  auto tree = std::make_shared<SampleTree>();
  std::istringstream lines(text);
  std::string line;
  for (long number = 1; std::getline(lines, line); ++number) {
    const std::vector<std::string_view> row = fields(line);
    if (row.empty() || row[0].starts_with('#')) continue;
    Vector values[2];
    bool numbers = row.size() == 6;
    for (std::size_t k = 0; numbers && k < 6; ++k) numbers = detail::parse_real(row[k], values[k / 3][k % 3]);
    if (!numbers && number == 1) continue;  // a header line
    const std::string where = path + ":" + std::to_string(number) + ": ";
    if (!numbers)
      throw InputError(where + "expected 6 numbers x y z ax ay az (comma or space separated), got " +
                       std::to_string(row.size()) + " fields");
    if (!std::isfinite(values[0][0]) || !std::isfinite(values[0][1]) || !std::isfinite(values[0][2]))
      throw InputError(where + "the sample's position is not finite");
    if (!usable(values[1])) throw InputError(where + "the fibre direction must be a non-zero finite vector");
    tree->points.push_back(values[0]);
    tree->directions.push_back(values[1]);
  }
  if (tree->points.empty()) throw InputError(path + ": no fibre samples (lines x y z ax ay az)");
  tree->index();
  field.samples_ = std::move(tree);
  return field;
}

FibreField::Vector FibreField::at(const Vector& centre, const std::string& cell) const {
  Vector a = direction_;
  if (kind_ == Kind::formula) {
    for (int c = 0; c < 3; ++c) a[c] = components_[c].evaluate(centre);
  } else if (kind_ == Kind::samples) {
    int best = -1;
    double distance = HUGE_VAL;
    samples_->nearest(centre, 0, static_cast<int>(samples_->points.size()), 0, best, distance);
    a = samples_->directions[static_cast<std::size_t>(best)];
  }
  if (!usable(a))
    throw InputError(owner_ + ": the fibre direction of " + cell + " (centre " + point_text(centre) + ") is " +
                     point_text(a) + ": not a non-zero finite vector");
  return a;
}

std::string FibreField::describe() const {
  switch (kind_) {
    case Kind::constant: return "constant " + point_text(direction_);
    case Kind::formula:
      return "formula [" + components_[0].text() + ", " + components_[1].text() + ", " + components_[2].text() + "]";
    case Kind::samples: return "file " + path_;
    default: return "none";
  }
}

}  // namespace tensormass

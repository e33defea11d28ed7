/// \file fibre_field.hpp
/// Where a material's fibres point, cell by cell: the direction a law with
/// fibre invariants (I4 .. I8, docs/laws.md) reads as per-cell constants.
/// A field is one of: a constant vector; three formulas of the cell centre's
/// rest position (x, y, z); or direction samples read from a file (each cell
/// takes the sample nearest its centre). Kernels normalise the direction.
#ifndef TENSORMASS_MODEL_FIBRE_FIELD_HPP
#define TENSORMASS_MODEL_FIBRE_FIELD_HPP

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "tensormass/common/expression.hpp"

namespace tensormass {

class FibreField {
 public:
  using Vector = std::array<double, 3>;

  /// No field: `given()` is false.
  FibreField() = default;
  /// The same direction in every cell.
  static FibreField constant(const Vector& direction, std::string owner);
  /// Components as formulas of x, y, z (the cell centre at rest); InputError
  /// naming `owner` on a formula that does not parse.
  static FibreField formula(const std::array<std::string, 3>& components, std::string owner);
  /// Samples x y z ax ay az, one per line of a CSV or whitespace-separated
  /// file (a header line and lines starting with # are skipped); InputError
  /// naming the file and line on anything else, or on a zero direction.
  static FibreField samples(const std::string& path, std::string owner);

  bool given() const { return kind_ != Kind::none; }
  /// The direction at a cell centre (3 coordinates); InputError naming the
  /// owner, `cell` (a description, for messages) and the point when it is
  /// zero or not finite.
  Vector at(const Vector& centre, const std::string& cell) const;
  /// "constant", "formula" or "file <path>", for messages and summaries.
  std::string describe() const;

 private:
  enum class Kind { none, constant, formula, samples };
  struct SampleTree;  // a k-d tree over the sample points (fibre_field.cpp)

  Kind kind_ = Kind::none;
  Vector direction_{};
  std::array<Expression, 3> components_;
  std::shared_ptr<const SampleTree> samples_;
  std::string owner_;
  std::string path_;
};

}  // namespace tensormass

#endif

/// \file track.hpp
/// Trajectory of a group's centroid over a run (scene key `output.track`),
/// written as `track_<group>.csv` in the output directory.
///
/// Centroid of a group of cells at displacement u:
///   C(u) = sum_c V_c * m_c(u) / sum_c V_c
/// over the group's cells c, with V_c the cell's rest volume (area in 2D) by
/// the kernel's default quadrature rule (`cell_volume`, mesh_quality.hpp:
/// exact for straight-sided cells) and m_c(u) the mean of the current
/// positions X_i + u_i of the cell's nodes (every node, mid-edge nodes
/// included). C is linear in u: C(u) = sum_i W_i (X_i + u_i) with fixed node
/// weights W_i = sum over the cells c around i of V_c / (n_c sum V), n_c the
/// cell's node count. m_c is the cell's volume centroid for simplices,
/// parallelograms, parallelepipeds and right prisms (so C is the group's
/// volume centroid on meshes of these cells), not for pyramids or curved cells.
///
/// CSV (io/track_csv.hpp, written row by row as the run goes): header `time,x,y,z,ux,uy,uz`, then one row per recorded
/// state (time in seconds, or the load factor for static solves), (x, y, z) = C(u) and (ux, uy, uz) = C(u) - C(u_first)
/// = S(u) - S(u_first), S(u) = sum_i W_i u_i (the first row's displacement is exactly 0, and S is evaluated as u_0 +
/// sum_i W_i (u_i - u_0), exact for a rigid translation); every number with 17 significant digits (round trip exact); z
/// = 0 in 2D.
#ifndef TENSORMASS_TRACK_HPP
#define TENSORMASS_TRACK_HPP

#include <array>
#include <span>
#include <string>
#include <vector>

#include "tensormass/io/track_csv.hpp"
#include "tensormass/mesh/mesh.hpp"

namespace tensormass {

/// The centroid of one group of cells, recorded step by step.
class GroupTrack {
 public:
  /// Weights of the cells of `group`; throws InputError when it has none.
  GroupTrack(const Mesh& mesh, const Group& group);
  /// Weights of the given mesh-wide cells, named `name` (for messages and files).
  GroupTrack(const Mesh& mesh, std::string name, std::span<const int> cells);

  const std::string& name() const { return name_; }
  /// The centroid at rest.
  const std::array<double, 3>& rest_centroid() const { return rest_centroid_; }
  /// The sum of the group's rest volumes (areas in 2D).
  double rest_volume() const { return rest_volume_; }
  /// The current centroid C(u); u holds mesh.dim components per node (node-major).
  std::array<double, 3> centroid(std::span<const double> u) const;
  /// The row of the state at `time`; the first call sets the reference of
  /// the displacements. The rows are not kept: the run streams them to the
  /// track file (io/streamed_file.hpp).
  TrackRow record(double time, std::span<const double> u);
  /// The nodes whose displacement the track reads (sorted, unique).
  const std::vector<int>& nodes() const { return nodes_; }
  /// The weighted displacement of the first row, which later rows are measured from.
  const std::array<double, 3>& first_shift() const { return first_; }
  /// Whether a row was recorded (the first shift is set).
  bool recorded() const { return recorded_; }
  /// Takes a saved first shift (a resumed run, whose rows so far are in its track file).
  void restore(const std::array<double, 3>& first_shift) {
    first_ = first_shift;
    recorded_ = true;
  }

 private:
  /// sum_i W_i v_i over the first min(dim, stride) components of v (`stride` values per node).
  std::array<double, 3> weighted_sum(std::span<const double> values, int stride) const;
  /// sum_i W_i u_i.
  std::array<double, 3> weighted_displacement(std::span<const double> u) const;

  std::string name_;
  int dim_ = 3;
  std::vector<int> nodes_;       ///< nodes of the group's cells, sorted, unique
  std::vector<double> weights_;  ///< W_i per entry of nodes_, summing to 1
  std::array<double, 3> rest_centroid_{};
  std::array<double, 3> first_{};  ///< weighted displacement of the first row
  double rest_volume_ = 0;
  bool recorded_ = false;
};

}  // namespace tensormass

#endif

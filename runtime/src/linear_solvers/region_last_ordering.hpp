// A fill-reducing ordering that eliminates a region's rows after all the
// others (internal header). The substitutions for a right-hand side on the
// region then run over the region's own supernodes only (FactorReach): its
// rows have no descendants outside it.
#ifndef TENSORMASS_LINEAR_SOLVERS_REGION_LAST_ORDERING_HPP
#define TENSORMASS_LINEAR_SOLVERS_REGION_LAST_ORDERING_HPP

#include <cholmod.h>

#include <span>
#include <vector>

#include "tensormass/assembly/sparse_matrix.hpp"

namespace tensormass::detail {

/// The rows at most `rings` steps from `rows` in A's graph (A stores both
/// triangles), ascending; `rows` itself for rings = 0.
std::vector<int> dilated_rows(const SparseMatrix& A, std::span<const int> rows, int rings);

/// A permutation of A's rows in CHOLMOD's convention (position k holds row
/// perm[k]; A.rows entries): the rows outside `region` first, then those of
/// `region` (distinct rows of A), each part ordered by METIS
/// (cholmod_metis) on the graph of its own rows.
/// Throws NumericalError when METIS fails.
std::vector<int> region_last_ordering(const SparseMatrix& A, std::span<const int> region, cholmod_common& common);

}  // namespace tensormass::detail

#endif

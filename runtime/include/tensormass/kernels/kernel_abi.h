/// \file kernel_abi.h
/// The C ABI of generated kernels: one `tm_kernel` per LES triple
/// (Law, Element, Split). Plain C so that any solver can call it.
///
/// Shapes (n = nodes, d = dim, dofs = n*d, Q = quadrature points):
///   rest_positions  n by d, node-major (x0 y0 z0 x1 ...)
///   params          `params` doubles: the law's parameters in `param_names` order
///                   (young, poisson for Hooke; c10, c01, kappa for Mooney-Rivlin)
///   consts          `consts` doubles per element, filled by `precompute`
///   u               dofs displacements, node-major
///   gradient        dofs: dW/du, the element's internal force
///   hessian         dofs by dofs, row-major, symmetric: d2W/du2
///   stress          Q by d by d: first Piola-Kirchhoff stress at each point
#ifndef TENSORMASS_KERNEL_ABI_H
#define TENSORMASS_KERNEL_ABI_H

#ifdef __cplusplus
extern "C" {
#endif

/// Codes `precompute` returns besides 0 (success) and q+1 (the rest Jacobian
/// at quadrature point q has a non-positive or non-finite determinant):
/// param_count differs from the kernel's `params`; or parameter p (0-based)
/// is not finite or outside its `param_limits` (TM_PRECOMPUTE_BAD_PARAM - p).
/// In every case but 0 the consts are unusable.
#define TM_PRECOMPUTE_PARAM_COUNT (-1)
#define TM_PRECOMPUTE_BAD_PARAM (-2)

/// Fills the element's consts from its rest node positions and the law's
/// `param_count` parameters; returns 0 or one of the codes above.
typedef int (*tm_precompute_fn)(const double* rest_positions, const double* params, int param_count, double* consts);
typedef double (*tm_energy_fn)(const double* u, const double* consts);
typedef void (*tm_gradient_fn)(const double* u, const double* consts, double* gradient);
typedef void (*tm_hessian_fn)(const double* u, const double* consts, double* hessian);
typedef void (*tm_gradient_hessian_fn)(const double* u, const double* consts, double* gradient, double* hessian);
typedef void (*tm_stress_fn)(const double* u, const double* consts, double* stress);

/// Batched entry points: `batch_width` (W) elements at once. Inputs in
/// structure-of-arrays layout, entry i of element l at [i*W + l] (so a loop
/// over the elements vectorises); outputs element by element:
///   u         dofs by W
///   consts    consts by W (each element's `precompute` output, transposed)
///   gradient  W by dofs (may be NULL in gradient_hessian_batch)
///   hessian   W by dofs*dofs, each element's Hessian row-major as above
///   stress    W by Q by d by d, each element's `stress` as above
/// A partial batch fills its unused lanes with a copy of a used one.
typedef void (*tm_gradient_batch_fn)(const double* u, const double* consts, double* gradient);
typedef void (*tm_gradient_hessian_batch_fn)(const double* u, const double* consts, double* gradient, double* hessian);
typedef void (*tm_stress_batch_fn)(const double* u, const double* consts, double* stress);

/// The law's bulk part U(J) (the anp split): out = {U(J), dU/dJ, d2U/dJ2}
/// for the element's consts (only the leading derived parameters are read).
/// Under a law flagged `linear`, J stands for 1 + tr(eps).
typedef void (*tm_bulk_fn)(double J, const double* consts, double* out);

/// Layout shared by every split: consts[0 .. derived_params) are the
/// parameters the law's energy reads (its derived ones, lam, mu, ..., or its
/// own constants when it declares none), then per quadrature point q the weight
/// w_q * det(J_q) followed by the shape gradients dN_j/dX_c stored as
/// G^T (d by n, row c holds all nodes); split-specific data follow.
/// The values a law accepts for one parameter, from the law file's `limits`:
/// lower < p (or lower <= p when lower_inclusive), likewise for upper;
/// -HUGE_VAL / HUGE_VAL where the law states no bound. NaN never passes.
typedef struct tm_param_limit {
  double lower;
  double upper;
  int lower_inclusive;
  int upper_inclusive;
} tm_param_limit;

typedef struct tm_kernel {
  const char* law;
  const char* element;
  const char* split;
  int dim;
  int nodes;
  int dofs;
  int quadrature_points;
  int params;                          ///< user parameters (length of `params`)
  int derived_params;                  ///< leading doubles of consts
  int consts;                          ///< doubles per element
  const char* const* param_names;      ///< params
  const tm_param_limit* param_limits;  ///< params
  tm_precompute_fn precompute;
  tm_energy_fn energy;
  tm_gradient_fn gradient;
  tm_hessian_fn hessian;
  tm_gradient_hessian_fn gradient_hessian;
  tm_stress_fn stress;
  long flops_energy;
  long flops_gradient;
  long flops_hessian;
  /// 1 when the energy is quadratic in u with a stress-free reference
  /// (Hooke): gradient = hessian * u and the hessian does not depend on u.
  int linear;
  /// 1 when the law is defined and restoring for det F <= 0 (stable
  /// neo-Hookean): the runtime lets such elements invert instead of stopping.
  int invertible;
  /// Elements per batched call (the SIMD width the kernels were built for:
  /// 8 with AVX-512, 4 with AVX, else 2); 0 when the kernel has no batched
  /// entry points and the three below are NULL. The `whole` split has them for
  /// the elements where they are faster (tri3, quad4, tri6, quad8, tet4,
  /// prism6, pyramid5; not hex8, tet10, hex20).
  int batch_width;
  tm_gradient_batch_fn gradient_batch;
  tm_gradient_hessian_batch_fn gradient_hessian_batch;
  tm_stress_batch_fn stress_batch;
  /// The law's bulk part (tm_bulk_fn): in the anp split, and in the whole
  /// split of a viscoelastic law that has one; NULL otherwise.
  tm_bulk_fn bulk;
  /// A viscoelastic law's Prony series (docs/viscoelasticity.md): term i has
  /// the weight params[prony_weights[i]] and the relaxation time
  /// params[prony_times[i]] (and, when prony_volumetric_weights is not NULL, the
  /// weight params[prony_volumetric_weights[i]] on the bulk part's stress).
  /// 0 and NULL for an elastic law. The kernels
  /// compute the instantaneous elastic response; the runtime's viscous part
  /// (assembly/viscous_part.hpp) adds the history.
  int prony_terms;
  const int* prony_weights;
  const int* prony_times;
  /// The same terms' weights on the bulk part's stress (params indices), or
  /// NULL when the bulk part does not relax.
  const int* prony_volumetric_weights;
} tm_kernel;

/// Static reference-element facts the runtime needs (meshes, criteria, output).
typedef struct tm_element_info {
  const char* name;
  int dim;
  int order;
  int nodes;
  int vtk_type;
  int gmsh_type;
  const int* vtk_order;   ///< vtk_order[k]: our index of the k-th VTK node
  const int* gmsh_order;  ///< gmsh_order[k]: our index of the k-th Gmsh node
  int edge_count;
  int edge_size;     ///< 2, or 3 with the mid-edge node
  const int* edges;  ///< edge_count by edge_size
  int face_count;
  const int* face_sizes;  ///< face_count
  const int* face_offsets;
  /// Concatenated: corners counter-clockwise from outside, then the mid-edge
  /// nodes of the face's edges c0-c1, c1-c2, ..., then the face-centre node.
  const int* faces;
  const double* reference_nodes;  ///< nodes by dim
  int quadrature_points;          ///< of the default rule
  const double* weights;          ///< quadrature_points
  const double* shape_values;     ///< quadrature_points by nodes
  const char* calculix_type;      ///< "" when CalculiX has no such element
  const int* calculix_order;
  /// Nodes 0 .. corner_count-1 are the corners; then come the mid-edge, the
  /// face and the interior nodes, in this order (docs/adding-an-element.md).
  int corner_count;
  double reference_volume;        ///< measure of the reference element
  const double* shape_gradients;  ///< quadrature_points by nodes by dim: dN/dr, dN/ds(, dN/dt)
  /// corner_count by nodes by dim: dN/dr, dN/ds(, dN/dt) at each corner; where a
  /// shape function is singular there (a pyramid's apex), the limit from the centroid.
  const double* corner_gradients;
} tm_element_info;

int tm_kernel_count(void);
const tm_kernel* tm_kernel_at(int index);
int tm_element_count(void);
const tm_element_info* tm_element_at(int index);

#ifdef __cplusplus
}
#endif

#endif

// Overlap of collision primitives (hadal::CollisionShape): exact point containment, and the excess
// volume a union of primitives counts more than once.
//
// Why: the surface fluid model integrates pressure over each link primitive's closed surface
// separately, so a region inside k primitives displaces k times its volume. The excess
//   E = integral over space of max(count(x) - 1, 0) dV,   count(x) = #shapes containing x,
// with centroid p_BE = (1/E) integral of max(count - 1, 0) x dV, is what buoyancy over-counts; the
// buoyancy it adds is rho g E at p_BE (subtract it).
//
// Method: E is zero outside the union of the pairwise intersections of the shapes' axis-aligned
// bounding boxes in B, so only that union (split into disjoint boxes) is searched; with no
// overlapping pair of boxes the result is exactly zero and nothing is sampled. Each box is refined
// adaptively (a k-d octree: a cell splits every axis at least half as long as its longest). A cell
// is classified per shape from the exact signed distance phi at its centre c and its half-diagonal
// r: phi(c) > r outside; phi(c) < -r or all 8 corners inside (shapes are convex) inside; else the
// shape is "mixed". With k shapes inside and none mixed, max(count - 1, 0) is constant on the cell
// and the cell is integrated exactly. For a mixed shape the cell's part inside it is bracketed
// between two plane cuts of the cell, both exact box volumes:
//   upper: the tangent plane at the point of the surface nearest c (a supporting plane: shapes are
//          convex),
//   lower: the same plane moved inwards by delta = rho - sqrt(rho^2 - s^2), s the cell's largest
//          distance from the normal line through c, where a ball of radius rho >= 2 r touching the
//          surface from inside at that point lies in the shape (sphere, capsule: rho = radius;
//          cylinder side: rho = radius while the cell stays between the caps), or delta = 0 where
//          the cell meets only one flat face (box face, cylinder cap); elsewhere (box edges,
//          cylinder rims, cells larger than rho / 2) the lower bound is an empty cut.
// In a cell inside no shape and cut by two (the integrand is then 1_a 1_b: overlap edges, and
// whole surfaces where faces are coplanar or shapes tangent), the two cuts are combined: by
// lo_a + lo_b - 1 <= . <= min(hi_a, hi_b), and, for nearly parallel or opposite normals, by
// turning one plane onto the other's normal (it moves by at most |n_a -+ n_b| r over the cell), which
// makes the cuts nest or form a slab, both exact.
// Each cell's integral thus lies in [lo, hi]; the estimate is the sum of the midpoints and
//   volume_error_bound = sum (hi - lo) / 2     (rigorous, up to floating-point rounding),
// which shrinks as O(h^2) (h the cell size) over smooth surfaces and faces, plus O(h^2) from the
// cells on edges and on intersection curves (sets of dimension one). Cells are refined widest
// interval first until the bound is within tolerance or the cell budget is spent. Where a search
// box is exactly the overlap (aligned boxes, a box inside an aligned box) the result is exact.
//
// Centroid and second moment, from the same leaves with no further refinement: in each leaf f is
// replaced by an estimate f_est built from the same planes, whose moments are exact (the cell
// clipped to the planes is a convex polyhedron, summed as tetrahedra), together with an envelope
// G >= |f - f_est| (pointwise) whose moments are exact too. Each mixed shape's part S of the cell
// lies between its lower and upper cuts, L <= S <= U, so:
//   where some shape contains the cell, f = (n_inside - 1) + sum over the mixed shapes of 1_S, and
//     each 1_S is estimated by 1_U for a flat cut (L = U: exact, G = 0; the cells that never refine
//     add nothing), else by (1_L + 1_U) / 2 with G = (1_U - 1_L) / 2 (L empty where no lower cut is
//     known: box edges, cylinder rims, large cells);
//   where nothing contains it and two shapes are mixed (overlap edges, coplanar faces), f = 1_Sa 1_Sb
//     lies between the two-plane clips 1_La 1_Lb and 1_Ua 1_Ub: f_est is their mean, G half their
//     difference;
//   where nothing contains it and three or more are mixed (surfaces meeting at a point; rare), the
//     weight (lo + hi) / 2 is spread evenly over the cell (bounded on its own, below).
// The raw moments of f_est are summed about a fixed point near the search regions; the centroid is
// p = centroid_B = (integral f_est x) / (integral f_est), and the second moment is shifted to it. As
// integral f_est (x - p) = 0,
//   |p_true - p| = |integral (f - f_est)(x - p)| / E_true
//                <= sqrt(integral G * integral G |x - p|^2) / (volume - volume_error_bound)
// (Cauchy-Schwarz over the sum of the leaves' envelopes), and
//   |S_true - S|_F = |integral (f - f_est)(x - p)(x - p)^T|_F <= integral G |x - p|^2,
// both exact sums of G's moments (volume, first moment, trace), linear in the leaves, so evaluated
// at p once it is known. Evenly spread leaves add, with f = f_min + f' (f' >= 0, integral
// F' <= hi - floor), a = c - p, u = x - c (|u| <= r, c the cell centre, h its half extents,
// D = diag(h_i^2)), the first moment error (F - w) a + integral f' u, at most (hi - lo)/2 |a| +
// (hi - floor) r, and the second moment error
//   (F - w)(a a^T + D/3) + a m^T + m a^T + (integral f' u u^T - F' D/3),   |m| <= F' r,
// at most (hi - lo)/2 (|a|^2 + |D|/3) + (hi - floor)(2 |a| r + sqrt(r^4 + |D|^2/9)). With the corner
// tests' slack (its volume times the search diameter, squared for S), centroid_error_bound and
// second_moment_error_bound are rigorous up to floating-point rounding and shrink as O(h^2) like the
// volume's: at relative_tolerance 1e-3, in the tests and in random pairs and triples of all four
// primitives, the centroid bound is 0.10-0.19 % of the excess's RMS radius (sqrt(tr S / E)), actual
// errors below 0.02 %, flat faces oblique to B's axes included; the second moment's bound 0.16-0.5 %
// of |S|, actual errors 0.07-0.15 %. Both fall about tenfold per tenfold smaller tolerance. The
// refinement is driven by the volume alone. (A two-plane clip in which a face crosses a plane more
// than once, possible only with vertices within rounding of it, falls back to even spreading; the
// clips are cut a few rounding allowances outside their planes, so that coplanar faces of two shapes
// clip cleanly, and the volume this may move is added to the slack.)
//
// Deterministic (no sampling at random). Cost is proportional to cells_evaluated: about 0.25 us a
// cell to classify, and a little more again for the moments (clipping the leaves, about half the
// cells: 0.2 us a plane, two planes per curved cut): a 1e-3 bound takes 20k-45k cells for one
// overlap of round shapes (15-30 ms), ~100k for an 8-shape vehicle with 7 overlaps, the default
// budget.
//
// Note: this is the excess of the smooth primitives. tessellate() (primitive_mesh.h) inscribes round
// shapes, so their meshes overlap less, by about (surface area of the overlap region) x (mean gap
// between mesh and surface: 0.53 % of the radius for a 32-segment sphere): some 2.5 % of E for
// two spheres of radius R at distance R, i.e. rho g times that in buoyancy.
// Units: m, m^3, m^5.
#pragma once

#include <Eigen/Geometry>

#include <cstddef>
#include <utility>
#include <vector>

#include "hadal/core/model.h"

namespace hadal::geometry {

// True if p_B lies in the closed solid of `shape` posed at X_BG in frame B (boundary included).
// Exact up to rounding in the transform: box |p_G,i| <= box_size_i / 2; sphere |p_G| <= radius;
// cylinder x^2 + y^2 <= radius^2 and |z| <= length / 2; capsule distance to the axis segment
// |z| <= length / 2 at most radius.
bool contains(const CollisionShape& shape, const Eigen::Isometry3d& X_BG, const Eigen::Vector3d& p_B);

// Signed distance from p_B to the surface of `shape` posed at X_BG (negative inside) [m].
double signed_distance(const CollisionShape& shape, const Eigen::Isometry3d& X_BG,
                       const Eigen::Vector3d& p_B);

// Axis-aligned bounding box of `shape` posed at X_BG, in B (tight for every primitive) [m].
Eigen::AlignedBox3d bounding_box(const CollisionShape& shape, const Eigen::Isometry3d& X_BG);

struct OverlapExcessOptions {
  // Refinement stops once volume_error_bound <= max(relative_tolerance * volume,
  // absolute_tolerance) ...
  double relative_tolerance = 1e-3;
  double absolute_tolerance = 1e-9;  // [m^3] (1 cm^3 displaces 10 g of water)
  // ... or when refining further would classify more than max_cells cells in total (then
  // converged is false; the bound is still valid).
  std::size_t max_cells = 100000;
};

struct OverlapExcess {
  double volume = 0.0;                                    // E [m^3]
  Eigen::Vector3d centroid_B = Eigen::Vector3d::Zero();   // p_BE, zero when volume is 0 [m]
  double volume_error_bound = 0.0;                        // |E_true - volume| <= this [m^3]
  double centroid_error_bound = 0.0;  // |p_BE_true - centroid_B| <= this [m] (inf if E may be 0)
  // S = integral of max(count - 1, 0) (x - p)(x - p)^T dV about p = centroid_B (symmetric, positive
  // semidefinite; zero when volume is 0) [m^5]; tr(S) 1 - S is the inertia at unit density. With
  // dp = p_true - p (|dp| <= centroid_error_bound): about a point o the second moment is
  // S + E (p - o)(p - o)^T + E ((p - o) dp^T + dp (p - o)^T), and about p_true S - E dp dp^T.
  Eigen::Matrix3d second_moment_B = Eigen::Matrix3d::Zero();
  // |S_true - second_moment_B|_F <= this, S_true about centroid_B [m^5].
  double second_moment_error_bound = 0.0;
  bool converged = true;              // the bound met the tolerance within max_cells
  std::size_t cells_evaluated = 0;    // cells classified (cost)
  // Pairs (i, j), i < j, indices into shapes_B, shown to share a region of positive volume (a cell
  // inside both, or the certain part of a cut). A pair whose overlap is thinner than the finest
  // cells may be missing; its whole contribution is then within volume_error_bound.
  std::vector<std::pair<int, int>> overlapping_pairs;
};

// The excess E of the shapes (each posed at X_BG in a common frame B), method above. Dimensions
// must be >= 0 (a degenerate shape has no volume and never overlaps).
OverlapExcess overlap_excess(const std::vector<std::pair<CollisionShape, Eigen::Isometry3d>>& shapes_B,
                             const OverlapExcessOptions& options = {});

}  // namespace hadal::geometry

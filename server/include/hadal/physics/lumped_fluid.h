// Lumped fluid model (Fossen, "Handbook of Marine Craft Hydrodynamics and Motion Control", 2011,
// ch. 4 and 6): buoyancy per link plus diagonal linear + quadratic damping of the whole vehicle. It
// is the baseline that the surface-based model (physics/hydrodynamics) refines. Added mass and
// Coriolis terms are not modelled here.
//
// Buoyancy, per link i with displaced volume V_i and centre of buoyancy Cb_i:
//   f_i   = -s_i rho V_i g_W                      [N], applied at p_WCb_i = X_WB X_BL_i p_LCb_i
//   s_i   = clamp((z_surface - (z_Cb_i - h_i/2)) / h_i, 0, 1)          submerged fraction [-]
// Approximation: the displaced volume is treated as a vertical column of height h_i centred on
// Cb_i, with h_i the vertical extent in W of the link's collision shapes (their world-z bounding
// interval, recomputed for the current attitude), or, for a link without shapes, the diameter of a
// sphere of volume V_i. This is exact for an upright box whose Cb is its centroid and a fair,
// continuous interpolation otherwise; the point of application stays at Cb_i (the shift of the
// centroid of the submerged part is neglected), so partially submerged righting moments are
// approximate.
//
// Damping, with nu = [u v w p q r] the velocity of B relative to the water in B axes
// (v_BWater_B = R_WB^T (v_WB - v_water_W), w_WB_B = R_WB^T w_WB):
//   tau_k = -s (D_l,k + D_q,k |nu_k|) nu_k    (k = 1..6, per axis; D from FluidSpec, >= 0)
// applied at B's origin (force R_WB tau_1..3, moment R_WB tau_4..6) and scaled by the vehicle's
// submerged fraction s = sum_i s_i V_i / sum_i V_i (s = 1 below the surface, 0 above, by the height
// of B's origin if the vehicle has no volume).
// Units: SI (m, kg, s, N, N m); volumes in m^3, density in kg/m^3.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "hadal/core/model.h"
#include "hadal/core/state.h"

namespace hadal::physics {

// Forces and moments on the vehicle; moments are about B's origin Bo, everything expressed in W.
struct LumpedFluidWrench {
  Eigen::Vector3d f_buoyancy_W = Eigen::Vector3d::Zero();    // [N]
  Eigen::Vector3d tau_buoyancy_W = Eigen::Vector3d::Zero();  // about Bo [N m]
  Eigen::Vector3d f_damping_W = Eigen::Vector3d::Zero();     // applied at Bo [N]
  Eigen::Vector3d tau_damping_W = Eigen::Vector3d::Zero();   // [N m]
  double submerged_fraction = 0.0;                           // volume-weighted s [-]

  Eigen::Vector3d f_W() const { return f_buoyancy_W + f_damping_W; }
  Eigen::Vector3d tau_W() const { return tau_buoyancy_W + tau_damping_W; }
};

class LumpedFluid {
 public:
  LumpedFluid(const VehicleSpec& vehicle, const WorldSpec& world);

  // Fluid wrench on the vehicle in state `body`; v_water_W is the water velocity at the vehicle
  // (zero until currents exist). Allocation-free.
  LumpedFluidWrench wrench(const RigidBodyState& body, const Eigen::Vector3d& v_water_W) const;

  // Submerged fraction s_i of link `link` when the vehicle is at X_WB.
  double link_submerged_fraction(int link, const Eigen::Isometry3d& X_WB) const;

  double total_volume() const { return total_volume_; }

 private:
  struct ShapeExtent {
    CollisionShapeType type;
    Eigen::Matrix3d R_BG;
    Eigen::Vector3d p_BG;
    Eigen::Vector3d half_size;  // box half extents [m]
    double radius;              // sphere, cylinder, capsule [m]
    double half_length;         // cylinder, capsule: half the cylindrical part [m]
  };
  struct LinkVolume {
    double volume;
    Eigen::Vector3d p_BCb;
    int first_shape;
    int num_shapes;
    double height_without_shapes;  // diameter of the sphere of the link's volume [m]
  };

  // Half the vertical extent in W of one shape (about its centre) when B has attitude R_WB.
  static double vertical_half_extent(const ShapeExtent& shape, const Eigen::Matrix3d& R_WB);

  std::vector<ShapeExtent> shapes_;
  std::vector<LinkVolume> links_;
  double total_volume_ = 0.0;
  double surface_z_;
  double density_;
  Eigen::Vector3d gravity_W_;
  Vector6d linear_damping_;
  Vector6d quadratic_damping_;
};

}  // namespace hadal::physics

// Seabed soil contact (paper: "Seabed Interaction and Terramechanics Modeling"; docs/ARCHITECTURE.md,
// "Soil contact"): Bekker pressure-sinkage under every face of a vehicle's surface that is pressed into
// the seabed, Janosi-Hanamoto shear along it, on the same per-face framework as the hydrodynamics, as
// the vehicle's force element in place of Bullet's rigid contact (YAML: the vehicle's
// `seabed_contact: soil`, the world's `soil`).
//
// Per face f of the surface in B (area A, outward unit normal n, centroid r_c, second area moment C per
// area; everything below in W at the step's start), with the seabed's height h and unit upward normal
// n_s under the centroid (geometry/seabed_height.h):
//   sinkage         z = n_s.z (h - z_c)                  the centroid's depth below the local seabed plane
//   bearing area    A_b = A max(0, -n . n_s)             the face's area projected on the seabed plane, for
//                                                        faces that face into the soil; a face touches
//                                                        when z > 0 and A_b > 0
//   pressure        p = (k_c / b + k_phi) z^n            Bekker
//   normal force    F_n = max(0, p - c_d (v . n_s)) A_b n_s     with normal damping; soil never pulls
//   shear strength  tau_max = c + p tan(phi)             Mohr-Coulomb
//   shear           j <- P_s j + v_t dt, |j| <= j_cap    the face's shear displacement (state), P_s the
//                                                        projection on the seabed plane, v_t the face's
//                                                        tangential velocity over the soil
//                   F_t = -A_b [tau_max (1 - e^(-|j|/K)) j/|j| + eta tau_max e^(-|j|/K) / K v_t],
//                   |F_t| <= A_b tau_max                  Janosi-Hanamoto, with damping
//   moment          tau = (r_c - p_WBcm) x (F_n + F_t)
// summed over the faces in contact.
//
// Where Hadal goes beyond the paper, and why:
// - Faces are split at the midpoint of their longest edge until no edge is longer than 10 cm: pressure
//   is sampled at face centroids, and a box's bottom as two triangles would be sampled at two diagonal
//   points, too few to resist rocking (a 0.3 m block pushed sideways rocked itself into sliding).
// - b is the width of the contact patch, not sqrt of each face's area. Bekker's b is the smaller
//   dimension of the loaded area; with b = sqrt(A_face) a plate's sinkage would depend on how finely it
//   is tessellated (k_c / b grows tenfold from 2 to 200 triangles). Each link's faces in contact form a
//   patch (a track, a pad, a skid); b = sqrt(12 lambda), lambda the smaller in-plane eigenvalue of the
//   patch's second area moment per area (each face's own moment plus its centroid's spread), projected
//   on the seabed plane: exactly the short side of a rectangle, the paper's sqrt(A) for a square.
// - The shear builds up with the shear displacement j (Janosi-Hanamoto), as the issue asks, instead of
//   the paper's full tau_max A opposing any velocity: a body at rest holds (j stops where the shear
//   balances the load: j = -K ln(1 - F / (A tau_max)), a few K) instead of being flipped by a force that
//   jumps with the sign of its velocity, and traction grows with slip. j is capped at
//   j_cap = K ln(1000) (the soil has yielded: 1 - e^(-j_cap/K) = 0.999), so that a body that slid and is
//   pushed back turns its shear round within a few K. A body pushed sideways with less than
//   A c + W tan(phi) therefore creeps j_eq and stops; with more it slides.
// - The shear has a damping term proportional to its tangent stiffness tau_max e^(-|j|/K) / K (Rayleigh
//   stiffness damping, time constant eta), so an elastic shear oscillation dies out; it vanishes as the
//   soil yields, and the clip |F_t| <= A_b tau_max keeps the saturated traction exactly A_b tau_max.
// - Bearing area: the paper puts p A n_s on every face below the surface. The walls of a sunk hull
//   would then carry it as much as its bottom; A_b is the area whose pressure the soil bears.
// - Tracks and belts: a link may have a belt velocity v_belt (its surface moving over the body, e.g. a
//   track driven by its sprocket: -V x_B under a track driving forward), added to the face's velocity. A belt element is in contact
//   for the time s / |v_belt| it took to travel from the patch's leading edge to the face (s measured
//   along the belt's motion), so its shear relaxes: dj/dt = v_t - (|v_belt| / s) j, integrated
//   implicitly. Under steady slip i = (V - v) / V this gives Bekker-Wong's j = i s, so a track of length
//   L carries (A c + W tan(phi)) [1 - K / (i L) (1 - e^(-i L / K))]: growing with slip and saturating at
//   A c + W tan(phi) (tested).
//
// Not modelled: bulldozing resistance of the soil pushed ahead of a sunk face, multi-pass compaction
// (the seabed is not deformed), rebound (unloading follows loading).
// Stability (explicit forces, semi-implicit Euler): the normal stiffness n p A / z and the shear's
// tau_max A / K must satisfy omega dt < 2 with omega^2 = stiffness / mass; the damping coefficients are
// capped per body at mass / dt (c_d A dt / m <= 1), so damping never destabilises a light body.
// Units: SI (m, s, N, Pa). Presets of published soils: physics/soil_presets.h.
#pragma once

#include <Eigen/Geometry>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "hadal/physics/force_element.h"
#include "hadal/physics/soil_spec.h"
#include "hadal/physics/surface_hydrodynamics.h"

namespace hadal::geometry {
class SeabedHeight;
struct TriangleMesh;
}  // namespace hadal::geometry

namespace hadal::physics {

struct SoilWrench {
  Eigen::Vector3d f_W = Eigen::Vector3d::Zero();    // [N]
  Eigen::Vector3d tau_W = Eigen::Vector3d::Zero();  // about p_WBcm [N m]
  Eigen::Vector3d normal_force_W = Eigen::Vector3d::Zero();  // sum of F_n [N]
  Eigen::Vector3d shear_force_W = Eigen::Vector3d::Zero();   // sum of F_t [N]
  std::vector<Eigen::Vector3d> link_shear_force_W;  // sum of F_t per link (tracks' loads) [N]
  double contact_area = 0.0;       // sum of A_b [m^2]
  double max_sinkage = 0.0;        // [m]
  std::size_t faces_in_contact = 0;
};

class SoilContact {
 public:
  // The faces of `mesh_B` (a vehicle's surface in B, geometry::vehicle_surface_B: a triangle's material
  // names its link, geometry::link_material). Zero-area faces are dropped. mass [kg] and dt [s] bound the
  // damping (header). Throws std::invalid_argument for malformed index arrays or parameters.
  SoilContact(const geometry::TriangleMesh& mesh_B, const SoilParameters& soil, double mass, double dt);
  // The same with soils by region: each face in contact takes the soil under its centroid.
  SoilContact(const geometry::TriangleMesh& mesh_B, SoilLayout layout, double mass, double dt);

  // The soil's wrench on the body in `motion` over `seabed`; advances `shear` (resized to num_faces()
  // if it is not) by one step. belt_velocity_B: empty, or per link the velocity of its surface relative
  // to the body, in B (a track's belt) [m/s].
  SoilWrench compute(const BodyMotion& motion, const geometry::SeabedHeight& seabed, SoilShearState& shear,
                     const std::vector<Eigen::Vector3d>& belt_velocity_B = {});

  std::size_t num_faces() const { return faces_.size(); }
  std::size_t num_links() const { return num_links_; }
  const SoilParameters& soil() const { return layout_.soils.front(); }
  // The width b of each link's contact patch in the last compute() (0 for a link not in contact) [m].
  const std::vector<double>& patch_widths() const { return patch_width_; }

 private:
  struct Face {
    double area;
    Eigen::Vector3d n_B, c_B;
    Eigen::Matrix3d C_B;  // second area moment about the centroid, per area [m^2]
    std::size_t link;
  };
  struct Contact {
    std::size_t face, region;
    double sinkage, bearing_area;
    Eigen::Vector3d c_W, n_s;
  };
  // Each link's contact patch: its width b, and for a belt its leading edge along the belt's motion.
  struct Patch {
    double area = 0.0;
    Eigen::Vector3d first = Eigen::Vector3d::Zero();   // sum A_b c
    Eigen::Matrix3d second = Eigen::Matrix3d::Zero();  // sum A_b c c^T (W)
    Eigen::Matrix3d own = Eigen::Matrix3d::Zero();     // sum A_b C (B axes: the faces' own moments)
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // sum A_b n_s
    Eigen::Vector3d belt_W = Eigen::Vector3d::Zero();
    double belt_speed = 0.0;
    Eigen::Vector3d belt_direction = Eigen::Vector3d::Zero();
    double leading_edge = INFINITY;                    // min over faces of (c . u - half length along u)
  };
  // A face's forces before the shear is clipped with its damping.
  struct FaceForce {
    Eigen::Vector3d elastic, damping, r;
    double limit;  // A_b tau_max
    std::size_t link;
  };
  SoilLayout layout_;
  std::vector<double> tan_phi_;  // per soil
  double mass_, dt_;
  std::vector<Face> faces_;
  std::size_t num_links_ = 0;
  // Each link's faces (faces_[begin, end)) and a sphere in B that holds their centroids.
  struct LinkFaces {
    std::size_t begin = 0, end = 0;
    Eigen::Vector3d center_B = Eigen::Vector3d::Zero();
    double radius = 0.0;
  };
  std::vector<LinkFaces> links_;
  std::vector<double> c_x_, c_y_, c_z_;  // the faces' centroids in B (the culling loop's inputs)
  std::vector<Contact> contacts_;      // scratch
  std::vector<Patch> patches_;         // scratch, per link
  std::vector<FaceForce> face_forces_; // scratch, per contact
  std::vector<double> patch_width_;    // per link
  bool shear_clear_ = true;            // every j is zero (skips clearing when out of contact)
};

// The soil as a vehicle's force element: SoilContact over the seabed, with the vehicle's shear state and
// its links' belt velocities from ForceInput.
class SoilForces : public ForceElement {
 public:
  SoilForces(const geometry::TriangleMesh& mesh_B, SoilLayout layout, const geometry::SeabedHeight& seabed,
             double mass, double dt);
  void add(const ForceInput& in, StepWrench& out) override;
  const SoilWrench& last() const { return last_; }
  std::size_t num_faces() const { return contact_.num_faces(); }

 private:
  SoilContact contact_;
  const geometry::SeabedHeight& seabed_;
  SoilWrench last_;
};

}  // namespace hadal::physics

// The equations of motion of an articulated vehicle in generalised coordinates, and the added mass of its
// bodies (issue 40; docs/ARCHITECTURE.md, "Articulated vehicles").
//
// Generalised velocity u = [v_W0; w_W0; qd]: the base body's centre-of-mass velocity and angular velocity
// in W (what Bullet's btMultiBody holds for its base), then the joint rates (Articulation's order); a fixed
// base drops the first six. Body k's centre-of-mass velocity and angular velocity in W are
// [v_k; w_k] = J_k u (J_k 6 x n), its acceleration J_k u_dot + a_k with the velocity-product ("bias")
// acceleration a_k = J_k_dot u. With each body's Newton-Euler equations at its centre of mass in W,
//   M = sum_k J_k^T diag(m_k 1, I_k) J_k,     c = sum_k J_k^T [m_k a_k_lin; I_k a_k_ang + w_k x I_k w_k],
// the motion is M u_dot + c = Q: the same equations Bullet's Featherstone step integrates (the test
// compares the two step by step). No J_k is formed: M (and the added mass's sum below) is summed by
// composite bodies (add_composite), every J_k^T W_k by the wrenches about W's origin summed over each
// joint's subtree (project), and J_k u_dot by the tree from the base out (accelerations), each O(bodies).
//
// Added mass (physics/added_mass.h has the single-body form): body k with M_A about its centre of mass in
// K axes feels the fluid's reaction, in K axes,
//   tau_A = -M_A nu_r_dot - C_A(nu_r) nu_r,   nu_r_dot = [R^T a_lin - w_K x v_rK; R^T a_ang],
// nu_r = [R^T (v_k - v_water); R^T w_k] relative to a current constant in W, R = R_WK. The part linear in
// u_dot moves to the left: (M + sum_k J_k^T R6 M_A R6^T J_k) u_dot = Q - c - c_A. Bullet knows only M, so
// each body is handed its reaction tau_A at that u_dot as an applied wrench: Bullet's step then follows the
// motion with the added mass (exact for any M_A, like the single-body conversion, and stable since no
// acceleration is differentiated). Contact and joint-limit impulses see the rigid bodies' inertia only.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <vector>

#include "hadal/core/model.h"
#include "hadal/physics/articulation.h"

namespace hadal::physics {

class ArticulatedDynamics {
 public:
  // A body's wrench at its centre of mass, in W: [f; tau].
  using Wrench = Vector6d;

  ArticulatedDynamics(const Articulation& articulation, bool fixed_base);

  // Evaluates a_k, M and c at the bodies' poses X_WK (Articulation::poses_W) and B's velocity (of B's
  // origin, in W) and the joint rates.
  void update(const std::vector<Eigen::Isometry3d>& X_WK, const Eigen::Vector3d& v_WB, const Eigen::Vector3d& w_WB,
              const Eigen::Ref<const Eigen::VectorXd>& qd);
  // The kinematic part of update() alone: the bodies' poses, centres of mass, velocities, inertias in W and u
  // (what momentum() needs). a_k, M and c keep the values of the last update().
  void update_kinematics(const std::vector<Eigen::Isometry3d>& X_WK, const Eigen::Vector3d& v_WB,
                         const Eigen::Vector3d& w_WB, const Eigen::Ref<const Eigen::VectorXd>& qd);

  int size() const { return n_; }  // of u
  const Eigen::VectorXd& u() const { return u_; }
  // M at the last update()'s state, summed on first need (the step itself never forms it: reactions()
  // sums M with the added mass, mass_times() multiplies by it).
  const Eigen::MatrixXd& mass_matrix() const;
  // out = M u_dot (M: the rigid bodies', at the last update()'s state), by the tree without forming M.
  void mass_times(const Eigen::VectorXd& u_dot, Eigen::VectorXd& out) const;
  const Eigen::VectorXd& bias() const { return c_; }
  // Body k's centre of mass in W, its velocity [v; w] in W, and its bias acceleration a_k.
  const Eigen::Vector3d& p_Wcm(int k) const { return p_Wcm_[static_cast<std::size_t>(k)]; }
  const Vector6d& velocity(int k) const { return V_[static_cast<std::size_t>(k)]; }
  const Vector6d& bias_acceleration(int k) const { return A_[static_cast<std::size_t>(k)]; }

  // The whole tree's mass, centre of mass, momentum, angular momentum and inertia about that centre (W);
  // without `inertia`, I_W is left zero.
  struct Momentum {
    double mass = 0.0;
    Eigen::Vector3d c_W = Eigen::Vector3d::Zero();
    Eigen::Vector3d P_W = Eigen::Vector3d::Zero();
    Eigen::Vector3d L_W = Eigen::Vector3d::Zero();
    Eigen::Matrix3d I_W = Eigen::Matrix3d::Zero();
  };
  Momentum momentum(bool inertia = true) const;

  // Q for body wrenches at the centres of mass (W), gravity g_W on every body, and joint torques.
  Eigen::VectorXd generalized_force(const std::vector<Wrench>& wrenches_W, const Eigen::Vector3d& g_W,
                                    const Eigen::VectorXd& joint_torques) const;
  void generalized_force(const std::vector<Wrench>& wrenches_W, const Eigen::Vector3d& g_W,
                         const Eigen::VectorXd& joint_torques, Eigen::VectorXd& Q) const;

  struct AddedMassBody {
    Matrix6d M_A = Matrix6d::Zero();                       // about the centre of mass, K axes (scaled)
    Eigen::Vector3d v_water_W = Eigen::Vector3d::Zero();   // the water's velocity at the centre of mass
    Eigen::Vector3d a_water_W = Eigen::Vector3d::Zero();   // its acceleration (waves), which the added mass feels
  };
  // Each body's added-mass reaction wrench (at its centre of mass, W) for the motion with applied body
  // wrenches `wrenches_W`, gravity and joint torques (above), plus the generalised constraint force
  // Q_c (contacts: size() entries, or none) that Bullet's solver will add, which the caller
  // estimates from the step before (Bullet's impulses see the rigid inertia only, and the joint solve
  // below would not know a grasp's contacts without it); coriolis: include C_A(nu_r) nu_r.
  std::vector<Wrench> added_mass_reactions(const std::vector<AddedMassBody>& added,
                                           const std::vector<Wrench>& wrenches_W, const Eigen::Vector3d& g_W,
                                           const Eigen::VectorXd& joint_torques,
                                           const Eigen::Ref<const Eigen::VectorXd>& Q_c, bool coriolis) const {
    Reactions out;
    reactions(added, wrenches_W, g_W, joint_torques, Q_c, coriolis, nullptr, out);
    return out.bodies;
  }

  // Joint torques taken implicitly over the step (num_dofs() entries each), solved with the added mass
  // (docs/ARCHITECTURE.md, "The joint solve"):
  //  - each joint's servo torque servo - servo_D qdd, kept within +-limit (a joint that would pass it takes
  //    the limit and loses its servo_D), and its viscous damping's implicit part -damping_D qdd (its explicit
  //    part is in joint_torques); both move to the left like added mass, so a stiff servo on a light wrist
  //    is stable at any step (physics/joint_servo.h);
  //  - its Coulomb friction (|tau_f| <= friction): a joint sticks (qd' = qd + dt qdd = 0) when a friction
  //    torque within the bound holds it, and otherwise slides with the bound against its motion;
  //  - its limits, hard stops at the position level: a joint whose step would end past a bound ends on it
  //    (q + dt qd' = bound) with whatever torque pushes it there, and leaves it when that torque would pull;
  //    lower == upper locks the joint.
  // The three meet in one solve over which joints are held (stuck or on a limit), which slide and which
  // servos saturate, repeated until none changes: the joints' block of (M + ...)^-1 is small (num_dofs()
  // square), so each pass is a small dense solve.
  struct ImplicitJoints {
    Eigen::VectorXd servo;      // [N m] or [N]
    Eigen::VectorXd servo_D;    // >= 0 [N m s^2/rad] or [N s^2/m]
    Eigen::VectorXd limit;      // > 0 (infinity: none)
    Eigen::VectorXd damping_D;  // >= 0
    Eigen::VectorXd friction;   // >= 0 [N m] or [N] (empty: none)
    Eigen::VectorXd lower, upper;  // [rad] or [m] (+-infinity or empty: none)
    Eigen::VectorXd q;          // the joints' positions at the step's start (with limits)
    double dt = 0.0;            // [s] the step (with friction or limits)
  };
  struct Reactions {
    std::vector<Wrench> bodies;    // each body's added-mass reaction (at its centre of mass, W)
    Eigen::VectorXd servo;         // with `implicit`: each joint's servo torque over the step
    Eigen::VectorXd held;          // with `implicit`: each joint's friction and limit torque over the step
    // The joint torques to apply: joint_torques + servo + held - damping_D qdd.
    Eigen::VectorXd joint_torques;
  };
  // Into `out`, whose storage a step's calls reuse (as this object's scratch: not for concurrent calls).
  void reactions(const std::vector<AddedMassBody>& added, const std::vector<Wrench>& wrenches_W,
                 const Eigen::Vector3d& g_W, const Eigen::VectorXd& joint_torques,
                 const Eigen::Ref<const Eigen::VectorXd>& Q_c, bool coriolis, const ImplicitJoints* implicit,
                 Reactions& out) const;

  // The wrench each moving joint transmits over a step with generalised acceleration u_dot (Bullet's
  // (u' - u) / dt, its constraints' and contacts' effects included): for body k >= 1, what its parent
  // applies on it and on every body beyond it, force and moment about the joint (K's origin), in W, by
  // Newton-Euler over that subtree: sum of (m a - F - m g) and (I alpha + w x I w - tau + r x (m a - F)),
  // a = J u_dot + the bias acceleration, external_W each body's applied wrench at its centre of mass
  // (fluid, added mass, contacts; not gravity, not joint torques). Element 0 is zero.
  std::vector<Wrench> joint_wrenches(const Eigen::VectorXd& u_dot, const std::vector<Wrench>& external_W,
                                     const Eigen::Vector3d& g_W) const;

  // What reactions() and joint_wrenches() work in, kept from call to call so that a step allocates nothing
  // (internal: its contents mean nothing between calls).
  struct Scratch {
    Eigen::MatrixXd M, K, Li, S;
    Eigen::VectorXd rhs, u_dot, r, qdd, servo, D, sliding, total;
    std::vector<Matrix6d> A_added, G_total;
    std::vector<Wrench> bias, F, Z;
    std::vector<char> has_added, mode, locked;
    std::vector<Eigen::Index> rows;
  };

 private:
  const Articulation& articulation_;
  bool fixed_base_;
  int n_;
  std::vector<Vector6d> V_, A_;
  std::vector<Eigen::Vector3d> p_Wcm_, o_W_;  // centres of mass, K's origins
  std::vector<Eigen::Matrix3d> R_WK_, I_W_;
  Eigen::VectorXd u_;
  mutable Eigen::MatrixXd M_;  // mass_matrix()'s, valid while mass_matrix_current_
  mutable bool mass_matrix_current_ = false;
  Eigen::VectorXd c_;
  std::vector<Vector6d> psi_;  // each moving body's joint column of the twist about W's origin (update())
  std::vector<Matrix6d> G_;    // each body's inertia about W's origin (update())
  std::vector<Wrench> F_;      // scratch of update(): each body's bias wrench about W's origin
  std::vector<Articulation::BodyVelocity> velocities_;  // scratch of update_kinematics()
  mutable Scratch scratch_;
  void add_composite(std::vector<Matrix6d>& G, Eigen::MatrixXd& M) const;
  void project(std::vector<Wrench>& F, Eigen::Ref<Eigen::VectorXd> Q) const;
  // J_k u_dot for every body into Z.
  void accelerations(const Eigen::VectorXd& u_dot, std::vector<Wrench>& Z) const;
  // Each body's twist rate about W's origin from u_dot alone (no bias), into Z: the parent's plus the
  // joint's column times its acceleration (accelerations() and mass_times()).
  void twist_rates(const Eigen::VectorXd& u_dot, std::vector<Wrench>& Z) const;
};

}  // namespace hadal::physics

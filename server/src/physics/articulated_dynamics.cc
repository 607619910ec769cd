#include "hadal/physics/articulated_dynamics.h"

#include <Eigen/Cholesky>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "hadal/physics/added_mass.h"

namespace hadal::physics {
namespace {

// A's leading n x n block = L L^T in place (L in its lower triangle, read from it; L^T is written into the
// strict upper triangle as well) for a small symmetric positive definite block (the generalised mass
// matrix: 6 + a few joints; the joint solve's rows), false when it is not. Plain loops: at this size
// Eigen's LLT and its triangular solves spend more in set-up and dispatch than in arithmetic. The sums
// run over rows of L, which are columns of L^T: contiguous in the column-major A.
bool cholesky_in_place(Eigen::MatrixXd& A, Eigen::Index n) {
  const Eigen::Index stride = A.outerStride();
  double* a = A.data();
  for (Eigen::Index j = 0; j < n; ++j) {
    double* column_j = a + j * stride;  // L^T's column j above the diagonal: L's row j
    double d = column_j[j];
    for (Eigen::Index k = 0; k < j; ++k) d -= column_j[k] * column_j[k];
    if (!(d > 0.0)) return false;
    d = std::sqrt(d);
    column_j[j] = d;
    for (Eigen::Index i = j + 1; i < n; ++i) {
      double* column_i = a + i * stride;
      double sum = column_j[i];  // A(i, j), the lower triangle
      for (Eigen::Index k = 0; k < j; ++k) sum -= column_i[k] * column_j[k];
      column_j[i] = sum / d;  // L(i, j)
      column_i[j] = column_j[i];  // L^T(j, i)
    }
  }
  return true;
}

// x = (L L^T)^-1 x in place, for L (n x n) from cholesky_in_place: forward substitution along L's rows (the
// upper triangle's columns), then backward along L's columns: both contiguous.
void cholesky_solve(const Eigen::MatrixXd& L, Eigen::Index n, double* x) {
  const Eigen::Index stride = L.outerStride();
  const double* l = L.data();
  for (Eigen::Index i = 0; i < n; ++i) {
    const double* column_i = l + i * stride;
    double sum = x[i];
    for (Eigen::Index k = 0; k < i; ++k) sum -= column_i[k] * x[k];
    x[i] = sum / column_i[i];
  }
  for (Eigen::Index i = n - 1; i >= 0; --i) {
    const double* column_i = l + i * stride;
    double sum = x[i];
    for (Eigen::Index k = i + 1; k < n; ++k) sum -= column_i[k] * x[k];
    x[i] = sum / column_i[i];
  }
}

// What each joint's servo, friction and limits give over the step (ArticulatedDynamics::ImplicitJoints):
// qdd = qdd0 + S tau. A joint is free (tau = servo - D qdd + its sliding friction), stuck (qd' = 0), on a
// limit (q' = the bound) or locked there; each pass solves the modes' rows for tau, then moves every joint
// whose result breaks its mode (a servo past its limit saturates, a stuck joint needing more than its
// friction slides, a sliding one that would turn back sticks, a step ending past a bound holds there, a
// limit that would pull lets go). The passes are bounded: a mode set that keeps changing keeps the last.
// Into w.total (servo + friction + limit) and w.servo (each servo's torque over the step).
void solve_joint_torques(const ArticulatedDynamics::ImplicitJoints& in, const Eigen::Ref<const Eigen::MatrixXd>& S,
                         const Eigen::Ref<const Eigen::VectorXd>& qdd0, const Eigen::Ref<const Eigen::VectorXd>& qd,
                         ArticulatedDynamics::Scratch& w) {
  enum Mode : char { kFree, kStuck, kLower, kUpper };
  // A bound is crossed when the step would end beyond it by more than this (rounding of a joint left on it).
  constexpr double kBoundTolerance = 1e-9;  // [rad] or [m]
  const Eigen::Index n = qdd0.size();
  const double dt = in.dt;
  const auto at = [](const Eigen::VectorXd& v, Eigen::Index j, double none) { return v.size() > j ? v[j] : none; };
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<char>& mode = w.mode;
  std::vector<char>& locked = w.locked;
  mode.assign(static_cast<std::size_t>(n), kFree);
  locked.assign(static_cast<std::size_t>(n), 0);
  Eigen::VectorXd& servo = w.servo;
  Eigen::VectorXd& D = w.D;
  Eigen::VectorXd& sliding = w.sliding;
  servo = in.servo;
  D = in.servo_D;
  sliding.setZero(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const auto i = static_cast<std::size_t>(j);
    locked[i] = at(in.lower, j, -kInf) >= at(in.upper, j, kInf);
    if (locked[i]) {
      mode[i] = kLower;
    } else if (at(in.friction, j, 0.0) > 0.0) {
      mode[i] = kStuck;
    }
  }
  Eigen::MatrixXd& K = w.K;
  Eigen::VectorXd& r = w.r;
  Eigen::VectorXd& tau = w.total;
  Eigen::VectorXd& qdd = w.qdd;
  std::vector<Eigen::Index>& rows = w.rows;
  K.resize(n, n);
  r.resize(n);
  tau.setZero(n);
  qdd = qdd0;
  const auto held = [&](Eigen::Index j, double bound) { return ((bound - in.q[j]) / dt - qd[j]) / dt; };
  for (Eigen::Index pass = 0; pass < 4 * n + 4; ++pass) {
    // A free joint's row is tau_j = servo_j + sliding_j - D_j (qdd0_j + S_j tau); a held one's is
    // S_j tau = target_j - qdd0_j. A free joint without D takes its torque as it is; every other free row,
    // divided by its D, leaves (S + diag(1 / D over the free ones)) over the remaining joints: symmetric
    // positive definite (S is, as a diagonal block of the inverse of one), so a Cholesky solves it.
    rows.clear();
    for (Eigen::Index j = 0; j < n; ++j) {
      if (mode[static_cast<std::size_t>(j)] == kFree && D[j] == 0.0) {
        tau[j] = servo[j] + sliding[j];
      } else {
        rows.push_back(j);
      }
    }
    const auto count = static_cast<Eigen::Index>(rows.size());
    for (Eigen::Index a = 0; a < count; ++a) {
      const Eigen::Index j = rows[static_cast<std::size_t>(a)];
      const char mj = mode[static_cast<std::size_t>(j)];
      double rhs;
      if (mj == kFree) {
        rhs = (servo[j] + sliding[j]) / D[j] - qdd0[j];
        K(a, a) = S(j, j) + 1.0 / D[j];
      } else {
        rhs = (mj == kStuck ? -qd[j] / dt : mj == kLower ? held(j, in.lower[j]) : held(j, in.upper[j])) - qdd0[j];
        K(a, a) = S(j, j);
      }
      for (Eigen::Index b = 0; b < a; ++b) K(a, b) = S(j, rows[static_cast<std::size_t>(b)]);
      for (Eigen::Index k = 0; k < n; ++k) {
        if (mode[static_cast<std::size_t>(k)] == kFree && D[k] == 0.0) rhs -= S(j, k) * tau[k];
      }
      r[a] = rhs;
    }
    if (!cholesky_in_place(K, count)) throw std::runtime_error("articulated dynamics: the joint solve is singular");
    cholesky_solve(K, count, r.data());
    for (Eigen::Index a = 0; a < count; ++a) tau[rows[static_cast<std::size_t>(a)]] = r[a];
    qdd.noalias() = qdd0 + S * tau;
    bool changed = false;
    for (Eigen::Index j = 0; j < n; ++j) {
      char& m = mode[static_cast<std::size_t>(j)];
      // The servo's law at this step's end saturates, or a saturated one whose law has come back within
      // its limit (a trial mode's acceleration, such as a moving joint stopped in one step, may have
      // saturated it) takes its law again: each by way of the unsaturated law, never from one limit
      // straight to the other (the law falls as qdd grows, so that would flip forever).
      if (in.servo_D[j] > 0.0) {
        const double law = in.servo[j] - in.servo_D[j] * qdd[j];
        if (D[j] > 0.0 && std::abs(law) > in.limit[j]) {
          servo[j] = std::copysign(in.limit[j], law);
          D[j] = 0.0;
          changed = true;
        } else if (D[j] == 0.0 && law * servo[j] < in.limit[j] * in.limit[j]) {
          servo[j] = in.servo[j];
          D[j] = in.servo_D[j];
          changed = true;
        }
      }
      const double lower = at(in.lower, j, -kInf), upper = at(in.upper, j, kInf);
      const double friction = at(in.friction, j, 0.0);
      const double other = tau[j] - (servo[j] - D[j] * qdd[j]);  // friction's and the limit's part
      const double q_end = in.q.size() > j ? in.q[j] + dt * (qd[j] + dt * qdd[j]) : 0.0;
      const char before = m;
      if (locked[static_cast<std::size_t>(j)]) continue;
      if ((m == kLower && other < 0.0) || (m == kUpper && other > 0.0)) {
        m = friction > 0.0 ? kStuck : kFree;
      } else if (m == kStuck && std::abs(other) > friction) {
        m = kFree;
        sliding[j] = std::copysign(friction, other);
      } else if (m == kFree && sliding[j] * (qd[j] + dt * qdd[j]) > 0.0) {
        m = kStuck;  // its friction would turn it back
      } else if (m != kLower && m != kUpper) {
        if (q_end < lower - kBoundTolerance) m = kLower;
        if (q_end > upper + kBoundTolerance) m = kUpper;
      }
      if (m != kFree) sliding[j] = 0.0;
      changed = changed || m != before;
    }
    if (!changed) break;
  }
  servo -= D.cwiseProduct(qdd);
}

// L^-1 for a lower-triangular L with a non-zero diagonal, by forward substitution column by column (a few
// joints: Eigen's blocked triangular solve costs more in set-up than in arithmetic at this size).
void lower_inverse(const Eigen::Ref<const Eigen::MatrixXd>& L, Eigen::MatrixXd& X) {
  const Eigen::Index n = L.rows();
  X.setZero(n, n);
  for (Eigen::Index j = 0; j < n; ++j) {
    X(j, j) = 1.0 / L(j, j);
    for (Eigen::Index i = j + 1; i < n; ++i) {
      double sum = 0.0;
      for (Eigen::Index k = j; k < i; ++k) sum += L(i, k) * X(k, j);
      X(i, j) = -sum / L(i, i);
    }
  }
}

// A body's spatial inertia about W's origin O, in W axes, acting on its twist [v_O; w] (v_O: the velocity
// of its point at O), from A, its inertia about its centre of mass c in W axes acting on [v_c; w]:
// T^T A T with T = [1, -[c]; 0, 1] (v_c = v_O - c x w), by blocks:
// [A11, A12 - A11 [c]; A21 + [c] A11, A22 - A21 [c] + [c] A12 - [c] A11 [c]]. A is symmetric (a rigid
// body's, an added mass: physics/fluid_spec.h checks it, or sums of them), so the lower-left block is the
// upper-right's transpose (A21 + [c] A11 = (A12 - A11 [c])^T as [c]^T = -[c]).
Matrix6d about_origin(const Matrix6d& A, const Eigen::Vector3d& c) {
  const Eigen::Matrix3d C = skew(c);
  const Eigen::Matrix3d B12 = A.topRightCorner<3, 3>() - A.topLeftCorner<3, 3>() * C;
  Matrix6d out;
  out.topLeftCorner<3, 3>() = A.topLeftCorner<3, 3>();
  out.topRightCorner<3, 3>() = B12;
  out.bottomLeftCorner<3, 3>() = B12.transpose();
  out.bottomRightCorner<3, 3>() = A.bottomRightCorner<3, 3>() - A.bottomLeftCorner<3, 3>() * C + C * B12;
  return out;
}

// A rigid body's (mass m, inertia I about its centre c, W axes) the same way: [m, -m [c]; m [c], I - m [c][c]].
Matrix6d rigid_about_origin(double m, const Eigen::Matrix3d& I, const Eigen::Vector3d& c) {
  const Eigen::Matrix3d C = skew(c);
  Matrix6d out;
  out.topLeftCorner<3, 3>() = m * Eigen::Matrix3d::Identity();
  out.topRightCorner<3, 3>() = -m * C;
  out.bottomLeftCorner<3, 3>() = m * C;
  out.bottomRightCorner<3, 3>() = I - m * C * C;
  return out;
}

// R6 A R6^T with R6 = diag(R, R), by blocks, for a symmetric A (its lower-left block is the upper-right's
// transpose; A's own rounding-level asymmetry, within fluid_spec's check, is dropped).
Matrix6d rotate_symmetric(const Matrix6d& A, const Eigen::Matrix3d& R) {
  Matrix6d out;
  out.topLeftCorner<3, 3>().noalias() = R * A.topLeftCorner<3, 3>() * R.transpose();
  out.topRightCorner<3, 3>().noalias() = R * A.topRightCorner<3, 3>() * R.transpose();
  out.bottomLeftCorner<3, 3>() = out.topRightCorner<3, 3>().transpose();
  out.bottomRightCorner<3, 3>().noalias() = R * A.bottomRightCorner<3, 3>() * R.transpose();
  return out;
}

// A wrench at c ([f; tau_c], W) as one about W's origin: [f; tau_c + c x f].
Vector6d wrench_about_origin(const Vector6d& W, const Eigen::Vector3d& c) {
  Vector6d out;
  out.head<3>() = W.head<3>();
  out.tail<3>() = W.tail<3>() + c.cross(W.head<3>());
  return out;
}

}  // namespace

ArticulatedDynamics::ArticulatedDynamics(const Articulation& articulation, bool fixed_base)
    : articulation_(articulation),
      fixed_base_(fixed_base),
      n_(articulation.num_dofs() + (fixed_base ? 0 : 6)) {
  const auto bodies = static_cast<std::size_t>(articulation.num_bodies());
  V_.assign(bodies, Vector6d::Zero());
  A_.assign(bodies, Vector6d::Zero());
  p_Wcm_.assign(bodies, Eigen::Vector3d::Zero());
  o_W_.assign(bodies, Eigen::Vector3d::Zero());
  R_WK_.assign(bodies, Eigen::Matrix3d::Identity());
  I_W_.assign(bodies, Eigen::Matrix3d::Zero());
  psi_.assign(bodies, Vector6d::Zero());
  G_.assign(bodies, Matrix6d::Zero());
  F_.assign(bodies, Wrench::Zero());
  u_ = Eigen::VectorXd::Zero(n_);
  M_ = Eigen::MatrixXd::Zero(n_, n_);
  c_ = Eigen::VectorXd::Zero(n_);
}

void ArticulatedDynamics::update_kinematics(const std::vector<Eigen::Isometry3d>& X_WK, const Eigen::Vector3d& v_WB,
                                            const Eigen::Vector3d& w_WB, const Eigen::Ref<const Eigen::VectorXd>& qd) {
  const Articulation& a = articulation_;
  if (static_cast<int>(X_WK.size()) != a.num_bodies() || qd.size() != a.num_dofs()) {
    throw std::invalid_argument("articulated dynamics: " + std::to_string(X_WK.size()) + " poses and " +
                                std::to_string(qd.size()) + " joint rates for " + std::to_string(a.num_bodies()) +
                                " bodies");
  }
  std::vector<Articulation::BodyVelocity>& velocity = velocities_;
  a.velocities_W(X_WK, v_WB, w_WB, qd, velocity);
  for (int k = 0; k < a.num_bodies(); ++k) {
    const auto i = static_cast<std::size_t>(k);
    const Articulation::Body& body = a.body(k);
    R_WK_[i] = X_WK[i].linear();
    p_Wcm_[i] = X_WK[i] * body.mass_K.p_BBcm;
    o_W_[i] = X_WK[i].translation();
    I_W_[i] = R_WK_[i] * body.mass_K.I_BBcm_B * R_WK_[i].transpose();
    const Eigen::Vector3d& w = velocity[i].w_WK;
    V_[i].head<3>() = velocity[i].v_WK + w.cross(p_Wcm_[i] - o_W_[i]);
    V_[i].tail<3>() = w;
  }
  u_.setZero();
  if (!fixed_base_) {
    u_.head<3>() = V_[0].head<3>();
    u_.segment<3>(3) = V_[0].tail<3>();
  }
  u_.tail(a.num_dofs()) = qd;
}

void ArticulatedDynamics::update(const std::vector<Eigen::Isometry3d>& X_WK, const Eigen::Vector3d& v_WB,
                                 const Eigen::Vector3d& w_WB, const Eigen::Ref<const Eigen::VectorXd>& qd) {
  update_kinematics(X_WK, v_WB, w_WB, qd);
  const Articulation& a = articulation_;
  // Each joint's column of the twist about W's origin, and each body's bias acceleration from its parent's.
  A_[0].setZero();
  for (int k = 1; k < a.num_bodies(); ++k) {
    const auto i = static_cast<std::size_t>(k);
    const Articulation::Body& body = a.body(k);
    Vector6d& A = A_[i];
    const auto p = static_cast<std::size_t>(body.parent);
    const Eigen::Vector3d& c_k = p_Wcm_[i];
    const Eigen::Vector3d& c_p = p_Wcm_[p];
    const Eigen::Vector3d& o_k = o_W_[i];
    const Eigen::Vector3d s = R_WK_[i] * body.axis_K;
    const Eigen::Vector3d& w = V_[i].tail<3>();
    const Eigen::Vector3d& w_p = V_[p].tail<3>();
    const Eigen::Vector3d alpha_p = A_[p].tail<3>();
    const Eigen::Vector3d a_p = A_[p].head<3>();
    const double rate = qd[k - 1];
    const Eigen::Vector3d r = c_k - c_p;
    // [o x s; s] (revolute), [s; 0] (prismatic).
    if (body.joint.type == JointType::kPrismatic) {
      psi_[i].head<3>() = s;
      psi_[i].tail<3>().setZero();
      A.tail<3>() = alpha_p;
      A.head<3>() = a_p + alpha_p.cross(r) + w_p.cross(w_p.cross(r)) + 2.0 * w_p.cross(s * rate);
    } else {
      psi_[i].head<3>() = o_k.cross(s);
      psi_[i].tail<3>() = s;
      const Eigen::Vector3d r1 = o_k - c_p, r2 = c_k - o_k;
      A.tail<3>() = alpha_p + w_p.cross(s * rate);
      A.head<3>() = a_p + alpha_p.cross(r1) + w_p.cross(w_p.cross(r1)) + A.tail<3>().cross(r2) + w.cross(w.cross(r2));
    }
  }
  c_.setZero();
  mass_matrix_current_ = false;
  for (int k = 0; k < a.num_bodies(); ++k) {
    const auto i = static_cast<std::size_t>(k);
    const double m = a.body(k).mass_K.mass;
    G_[i] = rigid_about_origin(m, I_W_[i], p_Wcm_[i]);
    // c's wrench: each body's Newton-Euler need at its bias acceleration.
    const Eigen::Vector3d& w = V_[i].tail<3>();
    Wrench h;
    h.head<3>() = m * A_[i].head<3>();
    h.tail<3>() = I_W_[i] * A_[i].tail<3>() + w.cross(I_W_[i] * w);
    F_[i] = wrench_about_origin(h, p_Wcm_[i]);
  }
  project(F_, c_);
}

const Eigen::MatrixXd& ArticulatedDynamics::mass_matrix() const {
  if (!mass_matrix_current_) {
    std::vector<Matrix6d>& G = scratch_.G_total;
    G = G_;
    M_.setZero(n_, n_);
    add_composite(G, M_);
    mass_matrix_current_ = true;
  }
  return M_;
}

void ArticulatedDynamics::mass_times(const Eigen::VectorXd& u_dot, Eigen::VectorXd& out) const {
  // Each body's twist rate about W's origin from u_dot alone (the tree from the base out), its inertia
  // about the origin times it, summed back down the tree by project: sum_k J_k^T A_k J_k u_dot.
  std::vector<Wrench>& Z = scratch_.Z;
  std::vector<Wrench>& F = scratch_.F;
  twist_rates(u_dot, Z);
  F.resize(Z.size());
  for (std::size_t i = 0; i < Z.size(); ++i) F[i].noalias() = G_[i] * Z[i];
  out.setZero(n_);
  project(F, out);
}

// M += sum_k J_k^T A_k J_k by composite bodies (Featherstone's CRBA) over the twists about W's origin:
// with G_k = A_k about the origin and Gc_k the sum of G over body k's subtree, a joint's column psi_j (and
// the base's six, Psi_B = [1, [c_0]; 0, 1] for u's [v_c0; w_0]) meets the joints on its path to the base:
// M_ij = psi_i^T Gc_b(j) psi_j for i on that path, zero between joints on different branches. G is summed
// in place. O(bodies x depth) where sum_k J_k^T A_k J_k is O(bodies x n^2).
void ArticulatedDynamics::add_composite(std::vector<Matrix6d>& G, Eigen::MatrixXd& M) const {
  const Articulation& a = articulation_;
  const int bodies = a.num_bodies();
  const int offset = fixed_base_ ? 0 : 6;
  for (int k = bodies - 1; k >= 1; --k) G[static_cast<std::size_t>(a.body(k).parent)] += G[static_cast<std::size_t>(k)];
  const Eigen::Vector3d& c_0 = p_Wcm_[0];
  for (int k = 1; k < bodies; ++k) {
    const auto i = static_cast<std::size_t>(k);
    const Vector6d F = G[i] * psi_[i];
    const int col = offset + k - 1;
    M(col, col) += psi_[i].dot(F);
    for (int p = a.body(k).parent; p >= 1; p = a.body(p).parent) {
      const double m_pk = psi_[static_cast<std::size_t>(p)].dot(F);
      M(offset + p - 1, col) += m_pk;
      M(col, offset + p - 1) += m_pk;
    }
    if (!fixed_base_) {
      // Psi_B^T F: the force, and its moment about c_0.
      Vector6d m_Bk;
      m_Bk.head<3>() = F.head<3>();
      m_Bk.tail<3>() = F.tail<3>() - c_0.cross(F.head<3>());
      M.block<6, 1>(0, col) += m_Bk;
      M.block<1, 6>(col, 0) += m_Bk.transpose();
    }
  }
  // Psi_B^T G Psi_B, Psi_B = [1, [c_0]; 0, 1]: the whole tree's inertia about c_0 (about_origin's T at -c_0).
  if (!fixed_base_) M.topLeftCorner<6, 6>() += about_origin(G[0], -c_0);
}

// Q += sum_k J_k^T W_k for wrenches F about W's origin (W_k moved there): the same composite sums, a
// joint's entry psi_j^T (the sum over its subtree), the base's Psi_B^T (the sum over all: the force and
// its moment about c_0). F is summed in place.
void ArticulatedDynamics::project(std::vector<Wrench>& F, Eigen::Ref<Eigen::VectorXd> Q) const {
  const Articulation& a = articulation_;
  const int offset = fixed_base_ ? 0 : 6;
  for (int k = a.num_bodies() - 1; k >= 1; --k) {
    const auto i = static_cast<std::size_t>(k);
    F[static_cast<std::size_t>(a.body(k).parent)] += F[i];
    Q[offset + k - 1] += psi_[i].dot(F[i]);
  }
  if (!fixed_base_) {
    Q.head<3>() += F[0].head<3>();
    Q.segment<3>(3) += F[0].tail<3>() - p_Wcm_[0].cross(F[0].head<3>());
  }
}

// J_k u_dot for every body (its centre of mass's acceleration and its angular one, W) by the same tree: the
// twist's rate about W's origin is the parent's plus the joint's column times its acceleration, then moved
// to the centre of mass.
void ArticulatedDynamics::accelerations(const Eigen::VectorXd& u_dot, std::vector<Wrench>& Z) const {
  twist_rates(u_dot, Z);
  for (std::size_t i = 0; i < Z.size(); ++i) Z[i].head<3>() -= p_Wcm_[i].cross(Z[i].tail<3>());
}

void ArticulatedDynamics::twist_rates(const Eigen::VectorXd& u_dot, std::vector<Wrench>& Z) const {
  const Articulation& a = articulation_;
  const int offset = fixed_base_ ? 0 : 6;
  Z.resize(static_cast<std::size_t>(a.num_bodies()));
  Z[0].setZero();
  if (!fixed_base_) {
    Z[0].head<3>() = u_dot.head<3>() + p_Wcm_[0].cross(u_dot.segment<3>(3));
    Z[0].tail<3>() = u_dot.segment<3>(3);
  }
  for (int k = 1; k < a.num_bodies(); ++k) {
    const auto i = static_cast<std::size_t>(k);
    Z[i] = Z[static_cast<std::size_t>(a.body(k).parent)] + psi_[i] * u_dot[offset + k - 1];
  }
}

ArticulatedDynamics::Momentum ArticulatedDynamics::momentum(bool inertia) const {
  Momentum out;
  for (int k = 0; k < articulation_.num_bodies(); ++k) {
    const double m = articulation_.body(k).mass_K.mass;
    out.mass += m;
    out.c_W += m * p_Wcm_[static_cast<std::size_t>(k)];
  }
  out.c_W /= out.mass;
  for (int k = 0; k < articulation_.num_bodies(); ++k) {
    const auto i = static_cast<std::size_t>(k);
    const double m = articulation_.body(k).mass_K.mass;
    const Eigen::Vector3d r = p_Wcm_[i] - out.c_W;
    out.P_W += m * V_[i].head<3>();
    out.L_W += r.cross(m * V_[i].head<3>()) + I_W_[i] * V_[i].tail<3>();
    if (inertia) out.I_W += I_W_[i] + m * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
  }
  return out;
}

std::vector<ArticulatedDynamics::Wrench> ArticulatedDynamics::joint_wrenches(const Eigen::VectorXd& u_dot,
                                                                             const std::vector<Wrench>& external_W,
                                                                             const Eigen::Vector3d& g_W) const {
  const int bodies = articulation_.num_bodies();
  std::vector<Wrench> out(static_cast<std::size_t>(bodies), Wrench::Zero());
  std::vector<Wrench>& Ju_dot = scratch_.Z;
  accelerations(u_dot, Ju_dot);
  // Children come after their parents: from the last body back, each adds its own need to what its
  // children passed it, then passes the sum to its parent (moved to the parent's joint).
  for (int k = bodies - 1; k >= 1; --k) {
    const auto i = static_cast<std::size_t>(k);
    const double m = articulation_.body(k).mass_K.mass;
    const Vector6d acceleration = Ju_dot[i] + A_[i];
    const Eigen::Vector3d w = V_[i].tail<3>();
    const Eigen::Vector3d F = m * acceleration.head<3>() - external_W.at(i).head<3>() - m * g_W;
    const Eigen::Vector3d N =
        I_W_[i] * acceleration.tail<3>() + w.cross(I_W_[i] * w) - external_W[i].tail<3>();
    out[i].head<3>() += F;
    out[i].tail<3>() += N + (p_Wcm_[i] - o_W_[i]).cross(F);
    const int parent = articulation_.body(k).parent;
    if (parent < 1) continue;
    const auto p = static_cast<std::size_t>(parent);
    out[p].head<3>() += out[i].head<3>();
    out[p].tail<3>() += out[i].tail<3>() + (o_W_[i] - o_W_[p]).cross(out[i].head<3>());
  }
  return out;
}

Eigen::VectorXd ArticulatedDynamics::generalized_force(const std::vector<Wrench>& wrenches_W,
                                                       const Eigen::Vector3d& g_W,
                                                       const Eigen::VectorXd& joint_torques) const {
  Eigen::VectorXd Q;
  generalized_force(wrenches_W, g_W, joint_torques, Q);
  return Q;
}

void ArticulatedDynamics::generalized_force(const std::vector<Wrench>& wrenches_W, const Eigen::Vector3d& g_W,
                                            const Eigen::VectorXd& joint_torques, Eigen::VectorXd& Q) const {
  Q.setZero(n_);
  Q.tail(articulation_.num_dofs()) = joint_torques;
  std::vector<Wrench>& F = scratch_.F;
  F.resize(wrenches_W.size());
  for (int k = 0; k < articulation_.num_bodies(); ++k) {
    const auto i = static_cast<std::size_t>(k);
    Wrench W = wrenches_W.at(i);
    W.head<3>() += articulation_.body(k).mass_K.mass * g_W;
    F[i] = wrench_about_origin(W, p_Wcm_[i]);
  }
  project(F, Q);
}

void ArticulatedDynamics::reactions(const std::vector<AddedMassBody>& added, const std::vector<Wrench>& wrenches_W,
                                    const Eigen::Vector3d& g_W, const Eigen::VectorXd& joint_torques,
                                    const Eigen::Ref<const Eigen::VectorXd>& Q_c, bool coriolis,
                                    const ImplicitJoints* implicit, Reactions& out) const {
  const auto bodies = static_cast<std::size_t>(articulation_.num_bodies());
  const int dofs = articulation_.num_dofs();
  Scratch& w = scratch_;
  out.bodies.assign(bodies, Wrench::Zero());
  out.joint_torques = joint_torques;
  std::vector<Wrench>& reactions = out.bodies;
  Eigen::MatrixXd& M = w.M;
  // Q: the applied wrenches, gravity and each body's added-mass velocity-product part, all about W's origin.
  Eigen::VectorXd& rhs = w.rhs;
  rhs.setZero(n_);
  rhs.tail(dofs) = joint_torques;
  rhs -= c_;
  if (Q_c.size() == n_) rhs += Q_c;
  // Per body: R6 M_A R6^T (the reaction's part in J u_dot) and its velocity-product part, in W.
  std::vector<Matrix6d>& A_added = w.A_added;
  std::vector<char>& has_added = w.has_added;
  std::vector<Wrench>& bias = w.bias;
  std::vector<Wrench>& F = w.F;
  std::vector<Matrix6d>& G_total = w.G_total;  // each body's rigid and added inertia about W's origin
  A_added.resize(bodies);
  has_added.assign(bodies, 0);
  bias.assign(bodies, Wrench::Zero());
  F.resize(bodies);
  G_total = G_;
  bool any = false;
  const bool moving_base = !fixed_base_;
  for (std::size_t i = 0; i < bodies; ++i) {
    Wrench W = wrenches_W.at(i);
    W.head<3>() += articulation_.body(static_cast<int>(i)).mass_K.mass * g_W;
    const Matrix6d& M_A = added.at(i).M_A;
    if (!M_A.isZero(0.0) && (i > 0 || moving_base)) {
      any = true;
      has_added[i] = 1;
      const Eigen::Matrix3d& R = R_WK_[i];
      const Eigen::Matrix3d R_KW = R.transpose();
      Vector6d nu_r;
      nu_r.head<3>() = R_KW * (V_[i].head<3>() - added[i].v_water_W);
      nu_r.tail<3>() = R_KW * V_[i].tail<3>();
      Vector6d nu_r_dot_bias;
      nu_r_dot_bias.head<3>() = R_KW * A_[i].head<3>() - nu_r.tail<3>().cross(nu_r.head<3>());
      nu_r_dot_bias.tail<3>() = R_KW * A_[i].tail<3>();
      Vector6d tau = -M_A * nu_r_dot_bias;
      if (!added[i].a_water_W.isZero(0.0)) {  // waves: the water's acceleration accelerates the added mass too
        Vector6d a_water = Vector6d::Zero();
        a_water.head<3>() = R_KW * added[i].a_water_W;
        tau += M_A * a_water;
      }
      if (coriolis) tau -= added_mass_coriolis(M_A, nu_r);
      bias[i].head<3>() = R * tau.head<3>();
      bias[i].tail<3>() = R * tau.tail<3>();
      W += bias[i];
      A_added[i] = rotate_symmetric(M_A, R);
      G_total[i] += about_origin(A_added[i], p_Wcm_[i]);
    }
    F[i] = wrench_about_origin(W, p_Wcm_[i]);
  }
  project(F, rhs);
  if (!any && implicit == nullptr) return;
  M.setZero(n_, n_);
  add_composite(G_total, M);
  Eigen::VectorXd& u_dot = w.u_dot;
  if (implicit == nullptr) {
    u_dot = M.ldlt().solve(rhs);
  } else {
    // u_dot = u0 + X tau for the joints' torques tau (the joints' block of u is its tail); their
    // accelerations qdd = qdd0 + S tau, S the joints' block of the inverse.
    M.diagonal().tail(dofs) += implicit->damping_D;
    // M is symmetric positive definite (masses, inertias > 0); L overwrites its lower triangle.
    if (!cholesky_in_place(M, n_)) throw std::runtime_error("articulated dynamics: the mass matrix is singular");
    const Eigen::MatrixXd& L = M;
    u_dot = rhs;
    cholesky_solve(L, n_, u_dot.data());
    // With M = L L^T, the joints' block of M^-1 is Li^T Li, Li = L22^-1 (L's joint block: the joints'
    // unit vectors, the last rows, stay zero above it under L^-1).
    lower_inverse(L.bottomRightCorner(dofs, dofs), w.Li);
    w.S = w.Li.transpose().lazyProduct(w.Li);  // small: no blocked product
    solve_joint_torques(*implicit, w.S, u_dot.tail(dofs), u_.tail(dofs), w);
    rhs.tail(dofs) += w.total;
    u_dot = rhs;
    cholesky_solve(L, n_, u_dot.data());
    out.servo = w.servo;
    out.held = w.total - w.servo;
    out.joint_torques += w.total - implicit->damping_D.cwiseProduct(u_dot.tail(dofs));
  }
  if (any) {
    std::vector<Wrench>& Ju_dot = w.Z;
    accelerations(u_dot, Ju_dot);
    for (std::size_t i = 0; i < bodies; ++i) {
      if (has_added[i]) reactions[i] = bias[i] - A_added[i] * Ju_dot[i];
    }
  }
}

}  // namespace hadal::physics

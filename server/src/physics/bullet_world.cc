#include "hadal/physics/bullet_world.h"

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <vector>

#include "hadal/geometry/triangle_mesh.h"
#include "hadal/physics/articulation.h"
#include "hadal/physics/multibody.h"

namespace hadal::physics {

namespace {

constexpr double kSeabedFriction = 0.8;
constexpr double kRestitution = 0.0;
constexpr double kSeabedMeshMargin = 0.001;  // [m]
constexpr double kMaxMargin = 0.01;      // [m]
constexpr double kMarginFraction = 0.2;  // of the smallest half extent
constexpr double kPlaceholderRadius = 0.01;  // [m] the collider of a body without shapes (collides with nothing)


// A body whose bounding box (Bullet's, already widened by the contact breaking threshold) stays this far
// above a flat seabed has no contact with it to find.
constexpr double kPlaneClearance = 0.05;  // [m]

// Bullet pairs every body with an infinite plane (its bounding box is unbounded), and a compound body's
// every shape then meets the plane in the narrow phase each step, contact or not (a work-class ROV
// hovering 0.9 m up: about 8 % of its step). A pair of the flat seabed (a plane, normal +z) and a body
// whose box is clear of it skips the narrow phase and empties its manifolds, as the narrow phase itself
// would have (no point within the breaking threshold); every other pair takes Bullet's own.
void seabed_aware_near_callback(btBroadphasePair& pair, btCollisionDispatcher& dispatcher,
                                const btDispatcherInfo& info) {
  const auto* a = static_cast<const btCollisionObject*>(pair.m_pProxy0->m_clientObject);
  const auto* b = static_cast<const btCollisionObject*>(pair.m_pProxy1->m_clientObject);
  const bool a_plane = a->getCollisionShape()->getShapeType() == STATIC_PLANE_PROXYTYPE;
  const bool b_plane = b->getCollisionShape()->getShapeType() == STATIC_PLANE_PROXYTYPE;
  if (a_plane != b_plane) {
    const auto* plane = static_cast<const btStaticPlaneShape*>((a_plane ? a : b)->getCollisionShape());
    const btBroadphaseProxy* other = a_plane ? pair.m_pProxy1 : pair.m_pProxy0;
    const btVector3& n = plane->getPlaneNormal();
    if (n.x() == 0.0 && n.y() == 0.0 && n.z() == 1.0 &&
        other->m_aabbMin.z() > plane->getPlaneConstant() + kPlaneClearance) {
      if (pair.m_algorithm != nullptr) {
        btManifoldArray manifolds;
        pair.m_algorithm->getAllContactManifolds(manifolds);
        for (int m = 0; m < manifolds.size(); ++m) manifolds[m]->clearManifold();
      }
      return;
    }
  }
  btCollisionDispatcher::defaultNearCallback(pair, dispatcher, info);
}

// Bullet's broadphase pairs every two colliders whose boxes overlap and leaves it to the narrow phase's
// needsCollision to drop two bodies of one multibody without self-collision (Hadal's multibodies have
// none: multibody.h). An arm's links overlap each other's boxes and the vehicle's frame, so a work-class
// ROV carried ~20 such pairs through the pair cache and the near callback every step. This filter keeps
// Bullet's own group and mask test and drops those pairs before they are made.
struct SelfCollisionFilter : btOverlapFilterCallback {
  bool needBroadphaseCollision(btBroadphaseProxy* p0, btBroadphaseProxy* p1) const override {
    if ((p0->m_collisionFilterGroup & p1->m_collisionFilterMask) == 0 ||
        (p1->m_collisionFilterGroup & p0->m_collisionFilterMask) == 0) {
      return false;
    }
    const auto* a = btMultiBodyLinkCollider::upcast(static_cast<const btCollisionObject*>(p0->m_clientObject));
    const auto* b = btMultiBodyLinkCollider::upcast(static_cast<const btCollisionObject*>(p1->m_clientObject));
    return a == nullptr || b == nullptr || a->m_multiBody != b->m_multiBody || a->m_multiBody->hasSelfCollision();
  }
};

btVector3 to_bt(const Eigen::Vector3d& v) { return btVector3(v.x(), v.y(), v.z()); }

Eigen::Vector3d to_eigen(const btVector3& v) { return Eigen::Vector3d(v.x(), v.y(), v.z()); }

btTransform to_bt(const Eigen::Isometry3d& X) {
  const Eigen::Matrix3d& R = X.linear();
  return btTransform(btMatrix3x3(R(0, 0), R(0, 1), R(0, 2),  //
                                 R(1, 0), R(1, 1), R(1, 2),  //
                                 R(2, 0), R(2, 1), R(2, 2)),
                     to_bt(X.translation()));
}

Eigen::Isometry3d to_eigen(const btTransform& X) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  const btMatrix3x3& R = X.getBasis();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out.linear()(r, c) = R[r][c];
  }
  out.translation() = to_eigen(X.getOrigin());
  return out;
}

double margin_for(double smallest_half_extent) {
  return std::min(kMaxMargin, kMarginFraction * smallest_half_extent);
}

std::unique_ptr<btCollisionShape> make_shape(const CollisionShape& shape) {
  switch (shape.type) {
    case CollisionShapeType::kBox: {
      const Eigen::Vector3d half = 0.5 * shape.box_size;
      auto box = std::make_unique<btBoxShape>(to_bt(half));
      box->setMargin(margin_for(half.minCoeff()));
      return box;
    }
    case CollisionShapeType::kSphere:
      return std::make_unique<btSphereShape>(shape.radius);
    case CollisionShapeType::kCylinder: {
      const double half_length = 0.5 * shape.length;
      auto cylinder =
          std::make_unique<btCylinderShapeZ>(btVector3(shape.radius, shape.radius, half_length));
      cylinder->setMargin(margin_for(std::min(shape.radius, half_length)));
      return cylinder;
    }
    case CollisionShapeType::kCapsule:
      // btCapsuleShapeZ(radius, height): height is the cylindrical part (half-height = length / 2).
      return std::make_unique<btCapsuleShapeZ>(shape.radius, shape.length);
  }
  return nullptr;
}

}  // namespace

struct BulletWorld::Impl {
  // A multibody collider and the collision filter it joins the world with.
  struct Collider {
    std::unique_ptr<btCollisionShape> shape;  // the body's compound, or the placeholder sphere
    std::unique_ptr<btMultiBodyLinkCollider> object;
    int group = btBroadphaseProxy::DefaultFilter;
    int mask = btBroadphaseProxy::AllFilter;
  };
  struct Vehicle {
    MassProperties mass;
    Eigen::Isometry3d X_PB;
    std::vector<std::unique_ptr<btCollisionShape>> children;
    std::unique_ptr<btCompoundShape> compound;
    std::unique_ptr<btRigidBody> body;
    bool soil_contact = false;  // seabed_contact soil: the soil's forces, not Bullet, meet the seabed
    bool is_static = false;     // VehicleSpec::is_static
    // Articulated vehicles only (body is null then): the tree, Bullet's multibody and one collider per body
    // (body order). The joints' limits and friction are not Bullet's: the simulation's implicit joint solve
    // gives them as joint torques (physics/articulated_dynamics.h).
    std::unique_ptr<Articulation> articulation;
    MultiBodyPtr multibody;
    std::vector<Collider> colliders;
  };
  // The collision group of static vehicles (Bullet's first free custom group after its own five).
  static constexpr int kStaticVehicleFilter = btBroadphaseProxy::CharacterFilter << 1;

  // Which of vehicle v's bodies `object` is (Articulation's numbering; a rigid vehicle's one body is 0), or -1.
  static int body_of(const Vehicle& v, const btCollisionObject* object) {
    if (!v.multibody) return object == v.body.get() ? 0 : -1;
    for (std::size_t k = 0; k < v.colliders.size(); ++k) {
      if (object == v.colliders[k].object.get()) return static_cast<int>(k);
    }
    return -1;
  }

  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  SelfCollisionFilter self_collision_filter;
  // A multibody world and solver only for a model with an articulated vehicle.
  std::unique_ptr<btSequentialImpulseConstraintSolver> solver;
  std::unique_ptr<btDiscreteDynamicsWorld> world;
  btMultiBodyDynamicsWorld* multibody_world = nullptr;  // `world`, when it is one

  // The seabed: a plane, or a BVH over the model's seabed mesh (shared, never modified, so Bullet
  // reads its float vertex and index arrays in place).
  std::shared_ptr<const geometry::TriangleMesh> seabed_mesh;
  std::unique_ptr<btTriangleIndexVertexArray> seabed_arrays;
  std::unique_ptr<btCollisionShape> seabed_shape;
  std::unique_ptr<btRigidBody> seabed;
  std::vector<Vehicle> vehicles;

  explicit Impl(bool multibodies) {
    dispatcher.setNearCallback(seabed_aware_near_callback);
    broadphase.getOverlappingPairCache()->setOverlapFilterCallback(&self_collision_filter);
    if (multibodies) {
      auto mb_solver = std::make_unique<btMultiBodyConstraintSolver>();
      auto mb_world = std::make_unique<btMultiBodyDynamicsWorld>(&dispatcher, &broadphase, mb_solver.get(),
                                                                 &configuration);
      multibody_world = mb_world.get();
      solver = std::move(mb_solver);
      world = std::move(mb_world);
    } else {
      solver = std::make_unique<btSequentialImpulseConstraintSolver>();
      world = std::make_unique<btDiscreteDynamicsWorld>(&dispatcher, &broadphase, solver.get(), &configuration);
    }
  }

  void add_bodies() {
    world->addRigidBody(seabed.get());
    // The seabed is static (StaticFilter, colliding with everything else); a vehicle on soil contact
    // leaves static bodies out of its mask, so Bullet never pairs it with the seabed.
    for (Vehicle& v : vehicles) {
      if (v.multibody) {
        multibody_world->addMultiBody(v.multibody.get());
        for (Collider& c : v.colliders) world->addCollisionObject(c.object.get(), c.group, c.mask);
      } else if (v.is_static) {
        // Its own group, so that a vehicle on soil contact (which leaves StaticFilter out) still meets it;
        // never paired with the seabed (or another static body).
        world->addRigidBody(v.body.get(), kStaticVehicleFilter,
                            btBroadphaseProxy::AllFilter ^ btBroadphaseProxy::StaticFilter ^ kStaticVehicleFilter);
      } else if (v.soil_contact) {
        world->addRigidBody(v.body.get(), btBroadphaseProxy::DefaultFilter,
                            btBroadphaseProxy::AllFilter ^ btBroadphaseProxy::StaticFilter);
      } else {
        world->addRigidBody(v.body.get());
      }
    }
  }

  void remove_bodies() {
    for (Vehicle& v : vehicles) {
      if (v.multibody) {
        for (Collider& c : v.colliders) world->removeCollisionObject(c.object.get());
        multibody_world->removeMultiBody(v.multibody.get());
      } else {
        world->removeRigidBody(v.body.get());
      }
    }
    world->removeRigidBody(seabed.get());
  }

  ~Impl() { remove_bodies(); }

  // The articulated vehicle's multibody and colliders.
  void make_articulated(Vehicle& v, const VehicleSpec& spec) {
    v.articulation = std::make_unique<Articulation>(spec.links);
    const Articulation& a = *v.articulation;
    v.mass = a.body(0).mass_K;
    v.X_PB = v.mass.X_BP.inverse();
    v.multibody = make_multibody(a, spec.is_static);
    for (int k = 0; k < a.num_bodies(); ++k) {
      const Articulation::Body& body = a.body(k);
      const Eigen::Isometry3d X_PK = body.mass_K.X_BP.inverse();
      Collider c;
      auto compound = std::make_unique<btCompoundShape>();
      for (int l : body.links) {
        for (const CollisionShape& shape : spec.links[static_cast<std::size_t>(l)].collisions) {
          v.children.push_back(make_shape(shape));
          compound->addChildShape(to_bt(X_PK * a.X_KL(l) * shape.X_LG), v.children.back().get());
        }
      }
      if (compound->getNumChildShapes() > 0) {
        c.shape = std::move(compound);
        if (k == 0 && spec.is_static) {
          c.group = kStaticVehicleFilter;
          c.mask = btBroadphaseProxy::AllFilter ^ btBroadphaseProxy::StaticFilter ^ kStaticVehicleFilter;
        }
      } else {
        c.shape = std::make_unique<btSphereShape>(kPlaceholderRadius);
        c.mask = 0;
      }
      c.object = std::make_unique<btMultiBodyLinkCollider>(v.multibody.get(), k - 1);
      c.object->setCollisionShape(c.shape.get());
      const int first_link = k == 0 ? 0 : a.body(k).joint_link;
      c.object->setFriction(spec.links.at(static_cast<std::size_t>(first_link)).friction);
      c.object->setRestitution(kRestitution);
      if (k == 0) {
        v.multibody->setBaseCollider(c.object.get());
      } else {
        v.multibody->getLink(k - 1).m_collider = c.object.get();
      }
      v.colliders.push_back(std::move(c));
    }
  }
};

BulletWorld::BulletWorld(const Model& model)
    : impl_(std::make_unique<Impl>(std::any_of(model.vehicles.begin(), model.vehicles.end(),
                                               [](const VehicleSpec& spec) { return is_articulated(spec.links); }))) {
  Impl& w = *impl_;
  w.world->setGravity(to_bt(model.world.gravity_W));

  const SeabedSpec& seabed = model.world.seabed;
  if (seabed.type == SeabedType::kPlane || !seabed.mesh) {
    w.seabed_shape = std::make_unique<btStaticPlaneShape>(btVector3(0, 0, 1), seabed.z);
  } else {
    w.seabed_mesh = seabed.mesh;
    const geometry::TriangleMesh& mesh = *w.seabed_mesh;
    btIndexedMesh part;
    part.m_numTriangles = static_cast<int>(mesh.num_triangles());
    part.m_triangleIndexBase = reinterpret_cast<const unsigned char*>(mesh.indices.data());
    part.m_triangleIndexStride = 3 * sizeof(std::uint32_t);
    part.m_indexType = PHY_INTEGER;
    part.m_numVertices = static_cast<int>(mesh.num_vertices());
    part.m_vertexBase = reinterpret_cast<const unsigned char*>(mesh.positions.data());
    part.m_vertexStride = 3 * sizeof(float);
    part.m_vertexType = PHY_FLOAT;
    w.seabed_arrays = std::make_unique<btTriangleIndexVertexArray>();
    w.seabed_arrays->addIndexedMesh(part, PHY_INTEGER);
    w.seabed_shape = std::make_unique<btBvhTriangleMeshShape>(w.seabed_arrays.get(), true);
    // Bullet's default 4 cm margin would float bodies above the surface; 1 mm keeps contact stable.
    w.seabed_shape->setMargin(kSeabedMeshMargin);
  }
  btRigidBody::btRigidBodyConstructionInfo seabed_info(0.0, nullptr, w.seabed_shape.get());
  seabed_info.m_friction = kSeabedFriction;
  seabed_info.m_restitution = kRestitution;
  w.seabed = std::make_unique<btRigidBody>(seabed_info);

  w.vehicles.reserve(model.vehicles.size());
  for (const VehicleSpec& spec : model.vehicles) {
    Impl::Vehicle v;
    v.soil_contact = spec.seabed_contact == SeabedContact::kSoil;
    v.is_static = spec.is_static;
    if (is_articulated(spec.links)) {
      w.make_articulated(v, spec);
      w.vehicles.push_back(std::move(v));
      continue;
    }
    v.mass = composite_mass_properties(spec.links);
    v.X_PB = v.mass.X_BP.inverse();
    v.compound = std::make_unique<btCompoundShape>();
    for (const LinkSpec& link : spec.links) {
      for (const CollisionShape& shape : link.collisions) {
        v.children.push_back(make_shape(shape));
        v.compound->addChildShape(to_bt(v.X_PB * link.X_BL * shape.X_LG), v.children.back().get());
      }
    }
    // A static vehicle (VehicleSpec::is_static) is a static Bullet body: mass 0, never integrated.
    btRigidBody::btRigidBodyConstructionInfo info(spec.is_static ? 0.0 : v.mass.mass, nullptr, v.compound.get(),
                                                  spec.is_static ? btVector3(0, 0, 0) : to_bt(v.mass.I_principal));
    info.m_friction = spec.links.empty() ? LinkSpec{}.friction : spec.links[0].friction;
    info.m_restitution = kRestitution;
    v.body = std::make_unique<btRigidBody>(info);
    v.body->setActivationState(DISABLE_DEACTIVATION);
    // Rigid-body gyroscopic moment -(I w) x w (world.dynamics.gyroscopic): Bullet's implicit
    // treatment (stable at large spin rates), or none.
    v.body->setFlags(model.world.dynamics.gyroscopic ? BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY : 0);
    w.vehicles.push_back(std::move(v));
  }
  w.add_bodies();
  for (int i = 0; i < num_vehicles(); ++i) {
    const VehicleSpec& spec = model.vehicles[i];
    RigidBodyState initial;
    initial.X_WB = spec.X_WB_initial;
    initial.v_WB = spec.v_WB_initial;
    if (const Articulation* a = articulation(i)) {
      Eigen::VectorXd q(a->num_dofs());
      for (int k = 1; k < a->num_bodies(); ++k) q[k - 1] = a->body(k).joint.initial;
      set_articulated_state(i, initial, q, Eigen::VectorXd::Zero(a->num_dofs()));
    } else {
      set_body_state(i, initial);
    }
  }
}

BulletWorld::~BulletWorld() = default;

int BulletWorld::num_vehicles() const { return static_cast<int>(impl_->vehicles.size()); }

const MassProperties& BulletWorld::mass_properties(int vehicle) const {
  return impl_->vehicles[vehicle].mass;
}

const Articulation* BulletWorld::articulation(int vehicle) const {
  return impl_->vehicles[vehicle].articulation.get();
}

RigidBodyState BulletWorld::body_state(int vehicle) const {
  const Impl::Vehicle& v = impl_->vehicles[vehicle];
  Eigen::Isometry3d X_WP;
  RigidBodyState out;
  Eigen::Vector3d v_WP;
  if (v.multibody) {
    X_WP = to_eigen(v.multibody->getBaseWorldTransform());
    out.w_WB = to_eigen(v.multibody->getBaseOmega());
    v_WP = to_eigen(v.multibody->getBaseVel());
  } else {
    X_WP = to_eigen(v.body->getCenterOfMassTransform());
    out.w_WB = to_eigen(v.body->getAngularVelocity());
    v_WP = to_eigen(v.body->getLinearVelocity());
  }
  out.X_WB = X_WP * v.X_PB;
  out.v_WB = v_WP + out.w_WB.cross(out.X_WB.translation() - X_WP.translation());
  return out;
}

void BulletWorld::set_body_state(int vehicle, const RigidBodyState& body) {
  Impl::Vehicle& v = impl_->vehicles[vehicle];
  if (v.multibody) {
    set_articulated_state(vehicle, body, joint_positions(vehicle), joint_velocities(vehicle));
    return;
  }
  const Eigen::Isometry3d X_WP = body.X_WB * v.mass.X_BP;
  const Eigen::Vector3d v_WP =
      body.v_WB + body.w_WB.cross(X_WP.translation() - body.X_WB.translation());
  // Velocities first: setCenterOfMassTransform copies them into the interpolation state.
  v.body->setLinearVelocity(to_bt(v_WP));
  v.body->setAngularVelocity(to_bt(body.w_WB));
  v.body->setCenterOfMassTransform(to_bt(X_WP));
  v.body->clearForces();
  if (v.body->getActivationState() != DISABLE_DEACTIVATION) {
    v.body->forceActivationState(DISABLE_DEACTIVATION);
  }
}

void BulletWorld::set_articulated_state(int vehicle, const RigidBodyState& body,
                                        const Eigen::Ref<const Eigen::VectorXd>& q,
                                        const Eigen::Ref<const Eigen::VectorXd>& qd) {
  Impl::Vehicle& v = impl_->vehicles[vehicle];
  set_multibody_state(*v.multibody, *v.articulation, body.X_WB, body.v_WB, body.w_WB, q, qd);
  v.multibody->clearForcesAndTorques();
  place_colliders(*v.multibody);  // Bullet refreshes them only within a step
}

Eigen::VectorXd BulletWorld::joint_positions(int vehicle) const {
  const Impl::Vehicle& v = impl_->vehicles[vehicle];
  return v.multibody ? multibody_joint_positions(*v.multibody) : Eigen::VectorXd();
}

Eigen::VectorXd BulletWorld::joint_velocities(int vehicle) const {
  const Impl::Vehicle& v = impl_->vehicles[vehicle];
  return v.multibody ? multibody_joint_velocities(*v.multibody) : Eigen::VectorXd();
}

void BulletWorld::body_poses_W(int vehicle, std::vector<Eigen::Isometry3d>& X_WK) const {
  const Impl::Vehicle& v = impl_->vehicles[vehicle];
  if (v.multibody) {
    collider_poses_W(*v.multibody, *v.articulation, X_WK);
  } else {
    X_WK.clear();
  }
}

void BulletWorld::joint_state(int vehicle, std::vector<double>& q, std::vector<double>& qd) const {
  const Impl::Vehicle& v = impl_->vehicles[vehicle];
  if (v.multibody) {
    multibody_joint_state(*v.multibody, q, qd);
  } else {
    q.clear();
    qd.clear();
  }
}

void BulletWorld::clear_contacts() {
  Impl& w = *impl_;
  w.remove_bodies();
  w.broadphase.resetPool(&w.dispatcher);  // empty now: resets the trees and stage counters
  w.solver->reset();
  w.add_bodies();
}

void BulletWorld::add_force_W(int vehicle, const Eigen::Vector3d& f_W,
                              const Eigen::Vector3d& p_WQ) {
  Impl::Vehicle& v = impl_->vehicles[vehicle];
  if (v.multibody) {
    add_body_force_W(vehicle, 0, f_W, p_WQ);
    return;
  }
  btRigidBody& body = *v.body;
  body.applyForce(to_bt(f_W), to_bt(p_WQ) - body.getCenterOfMassPosition());
}

void BulletWorld::add_torque_W(int vehicle, const Eigen::Vector3d& tau_W) {
  Impl::Vehicle& v = impl_->vehicles[vehicle];
  if (v.multibody) {
    add_body_torque_W(vehicle, 0, tau_W);
    return;
  }
  v.body->applyTorque(to_bt(tau_W));
}

void BulletWorld::add_body_force_W(int vehicle, int body, const Eigen::Vector3d& f_W, const Eigen::Vector3d& p_WQ) {
  physics::add_body_force_W(*impl_->vehicles[vehicle].multibody, body, f_W, p_WQ);
}

void BulletWorld::add_body_torque_W(int vehicle, int body, const Eigen::Vector3d& tau_W) {
  btMultiBody& mb = *impl_->vehicles[vehicle].multibody;
  if (body == 0) {
    mb.addBaseTorque(to_bt(tau_W));
  } else {
    mb.addLinkTorque(body - 1, to_bt(tau_W));
  }
}

void BulletWorld::add_body_wrench_W(int vehicle, int body, const Eigen::Vector3d& f_W, const Eigen::Vector3d& tau_W) {
  physics::add_body_wrench_W(*impl_->vehicles[vehicle].multibody, body, f_W, tau_W);
}

void BulletWorld::add_joint_torque(int vehicle, int joint, double tau) {
  impl_->vehicles[vehicle].multibody->addJointTorque(joint, tau);
}

void BulletWorld::step(double dt) { impl_->world->stepSimulation(dt, 0, dt); }

int BulletWorld::num_contact_points(int vehicle) const {
  const Impl::Vehicle& v = impl_->vehicles[vehicle];
  btCollisionDispatcher& dispatcher = impl_->dispatcher;
  int count = 0;
  for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
    const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
    if (Impl::body_of(v, manifold->getBody0()) >= 0 || Impl::body_of(v, manifold->getBody1()) >= 0) {
      count += manifold->getNumContacts();
    }
  }
  return count;
}

std::vector<Eigen::Matrix<double, 6, 1>> BulletWorld::contact_wrenches_W(int vehicle, double dt) const {
  const Impl::Vehicle& v = impl_->vehicles[vehicle];
  std::vector<Eigen::Matrix<double, 6, 1>> out(v.multibody ? v.colliders.size() : 1,
                                               Eigen::Matrix<double, 6, 1>::Zero());
  const auto add = [&](int body, const btVector3& impulse, const btVector3& point) {
    if (body < 0) return;
    const Eigen::Vector3d f_W = to_eigen(impulse) / dt;
    out[static_cast<std::size_t>(body)].head<3>() += f_W;
    out[static_cast<std::size_t>(body)].tail<3>() += to_eigen(point).cross(f_W);
  };
  btCollisionDispatcher& dispatcher = impl_->dispatcher;
  for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
    const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
    const int a = Impl::body_of(v, manifold->getBody0()), b = Impl::body_of(v, manifold->getBody1());
    if (a < 0 && b < 0) continue;
    for (int c = 0; c < manifold->getNumContacts(); ++c) {
      const btManifoldPoint& point = manifold->getContactPoint(c);
      // On body 0 along the normal (from 1 towards 0) and the friction directions; the opposite on body 1.
      const btVector3 impulse = point.m_normalWorldOnB * point.m_appliedImpulse +
                                point.m_lateralFrictionDir1 * point.m_appliedImpulseLateral1 +
                                point.m_lateralFrictionDir2 * point.m_appliedImpulseLateral2;
      add(a, impulse, point.getPositionWorldOnA());
      add(b, -impulse, point.getPositionWorldOnB());
    }
  }
  return out;
}

}  // namespace hadal::physics

#include "hadal/physics/bullet_world.h"

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <vector>

#include "hadal/geometry/triangle_mesh.h"

namespace hadal::physics {

namespace {

constexpr double kVehicleFriction = 0.5;
constexpr double kSeabedFriction = 0.8;
constexpr double kRestitution = 0.0;
constexpr double kSeabedMeshMargin = 0.001;  // [m]
constexpr double kMaxMargin = 0.01;      // [m]
constexpr double kMarginFraction = 0.2;  // of the smallest half extent

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
  struct Vehicle {
    MassProperties mass;
    Eigen::Isometry3d X_PB;
    std::vector<std::unique_ptr<btCollisionShape>> children;
    std::unique_ptr<btCompoundShape> compound;
    std::unique_ptr<btRigidBody> body;
    bool soil_contact = false;  // seabed_contact soil: the soil's forces, not Bullet, meet the seabed
    bool is_static = false;     // VehicleSpec::is_static
  };
  // The collision group of static vehicles (Bullet's first free custom group after its own five).
  static constexpr int kStaticVehicleFilter = btBroadphaseProxy::CharacterFilter << 1;

  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &configuration};

  // The seabed: a plane, or a BVH over the model's seabed mesh (shared, never modified, so Bullet
  // reads its float vertex and index arrays in place).
  std::shared_ptr<const geometry::TriangleMesh> seabed_mesh;
  std::unique_ptr<btTriangleIndexVertexArray> seabed_arrays;
  std::unique_ptr<btCollisionShape> seabed_shape;
  std::unique_ptr<btRigidBody> seabed;
  std::vector<Vehicle> vehicles;

  void add_bodies() {
    world.addRigidBody(seabed.get());
    // The seabed is static (StaticFilter, colliding with everything else); a vehicle on soil contact
    // leaves static bodies out of its mask, so Bullet never pairs it with the seabed.
    for (Vehicle& v : vehicles) {
      if (v.is_static) {
        // Its own group, so that a vehicle on soil contact (which leaves StaticFilter out) still meets it;
        // never paired with the seabed (or another static body).
        world.addRigidBody(v.body.get(), kStaticVehicleFilter,
                           btBroadphaseProxy::AllFilter ^ btBroadphaseProxy::StaticFilter ^ kStaticVehicleFilter);
      } else if (v.soil_contact) {
        world.addRigidBody(v.body.get(), btBroadphaseProxy::DefaultFilter,
                           btBroadphaseProxy::AllFilter ^ btBroadphaseProxy::StaticFilter);
      } else {
        world.addRigidBody(v.body.get());
      }
    }
  }

  ~Impl() {
    for (Vehicle& v : vehicles) world.removeRigidBody(v.body.get());
    world.removeRigidBody(seabed.get());
  }
};

BulletWorld::BulletWorld(const Model& model) : impl_(std::make_unique<Impl>()) {
  Impl& w = *impl_;
  w.world.setGravity(to_bt(model.world.gravity_W));

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
    v.is_static = spec.is_static;
    btRigidBody::btRigidBodyConstructionInfo info(spec.is_static ? 0.0 : v.mass.mass, nullptr, v.compound.get(),
                                                  spec.is_static ? btVector3(0, 0, 0) : to_bt(v.mass.I_principal));
    info.m_friction = kVehicleFriction;
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
    set_body_state(i, initial);
  }
}

BulletWorld::~BulletWorld() = default;

int BulletWorld::num_vehicles() const { return static_cast<int>(impl_->vehicles.size()); }

const MassProperties& BulletWorld::mass_properties(int vehicle) const {
  return impl_->vehicles[vehicle].mass;
}

RigidBodyState BulletWorld::body_state(int vehicle) const {
  const Impl::Vehicle& v = impl_->vehicles[vehicle];
  const Eigen::Isometry3d X_WP = to_eigen(v.body->getCenterOfMassTransform());
  RigidBodyState out;
  out.X_WB = X_WP * v.X_PB;
  out.w_WB = to_eigen(v.body->getAngularVelocity());
  out.v_WB = to_eigen(v.body->getLinearVelocity()) +
             out.w_WB.cross(out.X_WB.translation() - X_WP.translation());
  return out;
}

void BulletWorld::set_body_state(int vehicle, const RigidBodyState& body) {
  Impl::Vehicle& v = impl_->vehicles[vehicle];
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

void BulletWorld::clear_contacts() {
  Impl& w = *impl_;
  for (Impl::Vehicle& v : w.vehicles) w.world.removeRigidBody(v.body.get());
  w.world.removeRigidBody(w.seabed.get());
  w.broadphase.resetPool(&w.dispatcher);  // empty now: resets the trees and stage counters
  w.solver.reset();
  w.add_bodies();
}

void BulletWorld::add_force_W(int vehicle, const Eigen::Vector3d& f_W,
                              const Eigen::Vector3d& p_WQ) {
  btRigidBody& body = *impl_->vehicles[vehicle].body;
  body.applyForce(to_bt(f_W), to_bt(p_WQ) - body.getCenterOfMassPosition());
}

void BulletWorld::add_torque_W(int vehicle, const Eigen::Vector3d& tau_W) {
  impl_->vehicles[vehicle].body->applyTorque(to_bt(tau_W));
}

void BulletWorld::step(double dt) { impl_->world.stepSimulation(dt, 0, dt); }

int BulletWorld::num_contact_points(int vehicle) const {
  const btRigidBody* body = impl_->vehicles[vehicle].body.get();
  btCollisionDispatcher& dispatcher = impl_->dispatcher;
  int count = 0;
  for (int m = 0; m < dispatcher.getNumManifolds(); ++m) {
    const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
    if (manifold->getBody0() == body || manifold->getBody1() == body) {
      count += manifold->getNumContacts();
    }
  }
  return count;
}

}  // namespace hadal::physics

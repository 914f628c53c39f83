// Rigid-body destruction with Bullet 3.24 (the only Bullet translation unit).
//
// Determinism: one single-threaded btDiscreteDynamicsWorld, bodies and constraints added
// in piece / bond order, a fixed step passed to stepSimulation with maxSubSteps = 0 (no
// time accumulator), the solver's order randomisation left off. Hulls are built in
// parallel but each depends on its piece alone.
#include <dawnforge/sim/rigidbody.hpp>

#include "bond_stress.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/seed.hpp>
#include <dawnforge/core/union_find.hpp>

#include <btBulletDynamicsCommon.h>
#include <LinearMath/btConvexHullComputer.h>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/quaternion.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>

namespace dawnforge::sim {

namespace {

btVector3 bt(const glm::dvec3& v) { return btVector3(btScalar(v.x), btScalar(v.y), btScalar(v.z)); }
glm::dvec3 toGlm(const btVector3& v) { return {double(v.x()), double(v.y()), double(v.z())}; }
btQuaternion bt(const glm::dquat& q) { return btQuaternion(btScalar(q.x), btScalar(q.y), btScalar(q.z), btScalar(q.w)); }
glm::dquat toGlm(const btQuaternion& q) { return glm::dquat(double(q.w()), double(q.x()), double(q.y()), double(q.z())); }

// The collision hull of one piece in its principal frame: the convex hull of the mesh,
// shrunk by the margin (Bullet adds it back), cut down to a vertex budget by farthest
// point sampling (ties to the lowest index, so the choice is deterministic).
struct Hull {
    std::vector<btVector3> points;
    btScalar margin = 0;
};

Hull buildHull(const RigidPiece& piece, const glm::dmat3& axes, int budget, double margin) {
    std::vector<btScalar> coords;
    coords.reserve(piece.mesh.positions.size() * 3);
    const glm::dmat3 toBody = glm::transpose(axes);
    for (const glm::vec3& p : piece.mesh.positions) {
        const glm::dvec3 b = toBody * glm::dvec3(p);
        coords.insert(coords.end(), {btScalar(b.x), btScalar(b.y), btScalar(b.z)});
    }
    Hull hull;
    btConvexHullComputer computer;
    const btScalar shrunk = computer.compute(coords.data(), int(3 * sizeof(btScalar)), int(coords.size() / 3),
                                             btScalar(margin), btScalar(0.25));
    std::vector<btVector3> all;
    if (shrunk >= 0 && computer.vertices.size() >= 4) {
        for (int i = 0; i < computer.vertices.size(); ++i) all.push_back(computer.vertices[i]);
        hull.margin = std::max(shrunk, btScalar(1e-4));
    } else {  // a flat or tiny piece: keep its points, a small margin
        for (std::size_t i = 0; i + 2 < coords.size(); i += 3) all.emplace_back(coords[i], coords[i + 1], coords[i + 2]);
        hull.margin = btScalar(1e-4);
    }
    if (int(all.size()) <= budget) {
        hull.points = std::move(all);
        return hull;
    }
    std::vector<btScalar> nearest(all.size(), std::numeric_limits<btScalar>::max());
    std::size_t pick = 0;
    for (std::size_t i = 1; i < all.size(); ++i)
        if (all[i].length2() > all[pick].length2()) pick = i;
    for (int n = 0; n < budget; ++n) {
        hull.points.push_back(all[pick]);
        std::size_t next = 0;
        btScalar best = -1;
        for (std::size_t i = 0; i < all.size(); ++i) {
            nearest[i] = std::min(nearest[i], (all[i] - all[pick]).length2());
            if (nearest[i] > best) { best = nearest[i]; next = i; }
        }
        pick = next;
    }
    return hull;
}

// Pieces glued into one cluster (connected through unbroken bonds) move as one: they do
// not collide with each other. Besides being right, this skips the narrow phase for the
// thousands of neighbouring pairs in an intact structure, most of the cost of a step.
// User indices of bodies that are not pieces.
constexpr int kStatic = -1;   // ground plane, projectile
constexpr int kSupport = -2;  // SimulationSettings::support
constexpr int kCollider = -3; // SimulationSettings::colliders

class ClusterDispatcher : public btCollisionDispatcher {
public:
    using btCollisionDispatcher::btCollisionDispatcher;
    std::vector<int> cluster;  // per piece (body user index)
    std::optional<Support> support;

    // Bullet asks again at every step for every overlapping pair, so this may change with
    // where the pieces are.
    bool needsCollision(const btCollisionObject* a, const btCollisionObject* b) override {
        const int i = a->getUserIndex(), j = b->getUserIndex();
        if (i >= 0 && j >= 0 && cluster[std::size_t(i)] == cluster[std::size_t(j)]) return false;
        if (support && (i == kSupport || j == kSupport || i == kCollider || j == kCollider)) {
            const btCollisionObject* piece = i >= 0 ? a : j >= 0 ? b : nullptr;
            if (piece) {
                const btVector3& p = piece->getWorldTransform().getOrigin();
                const bool over = p.x() >= support->min.x && p.x() <= support->max.x && p.z() >= support->min.y &&
                                  p.z() <= support->max.y;
                if (over != (i == kSupport || j == kSupport)) return false;  // the support holds it, or the colliders do
            }
        }
        return btCollisionDispatcher::needsCollision(a, b);
    }

    // Contacts of pairs that no longer collide (a piece that left the support, or came over
    // it) would stay in their manifolds and still push: empty them.
    void dropStaleContacts() {
        if (!support) return;
        for (int m = 0; m < getNumManifolds(); ++m) {
            btPersistentManifold* manifold = getManifoldByIndexInternal(m);
            if (manifold->getNumContacts() > 0 && !needsCollision(manifold->getBody0(), manifold->getBody1()))
                manifold->clearManifold();
        }
    }
};

// Everything Bullet needs alive while the world runs. Members are declared so that the
// world is destroyed first; constraints are removed from the bodies before that.
struct World {
    std::vector<std::unique_ptr<btCollisionShape>> shapes;
    std::vector<std::unique_ptr<btTriangleIndexVertexArray>> triangleArrays;
    std::vector<std::vector<int>> colliderIndices;
    std::vector<std::vector<btScalar>> colliderVertices;
    std::vector<std::unique_ptr<btRigidBody>> bodies;  // pieces first (index = piece), then ground, colliders, projectile
    std::vector<std::unique_ptr<btTypedConstraint>> constraints;
    btDefaultCollisionConfiguration configuration;
    ClusterDispatcher dispatcher{&configuration};
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    std::unique_ptr<btDiscreteDynamicsWorld> world =
        std::make_unique<btDiscreteDynamicsWorld>(&dispatcher, &broadphase, &solver, &configuration);

    ~World() {
        for (auto& c : constraints) world->removeConstraint(c.get());
        for (auto& b : bodies) world->removeRigidBody(b.get());
        world.reset();
    }
};

struct BodyInfo {
    glm::dquat toMesh{1.0, 0.0, 0.0, 0.0};  // body orientation → mesh orientation (conjugate of the principal frame)
    glm::dvec3 moments{0.0};
    double mass = 0.0;
};

double energyOf(const btRigidBody& body, const BodyInfo& info, const glm::dvec3& gravity) {
    const glm::dvec3 v = toGlm(body.getLinearVelocity());
    const glm::dvec3 w = toGlm(body.getAngularVelocity());
    const glm::dquat q = toGlm(body.getCenterOfMassTransform().getRotation());
    const glm::dvec3 wl = glm::conjugate(q) * w;  // in the principal frame
    const glm::dvec3 x = toGlm(body.getCenterOfMassPosition());
    return 0.5 * info.mass * glm::dot(v, v) + 0.5 * glm::dot(info.moments, wl * wl) - info.mass * glm::dot(gravity, x);
}

void checkSettings(std::span<const RigidPiece> pieces, std::span<const Bond> bonds, const SimulationSettings& s) {
    if (pieces.empty()) throw InputError("there are no pieces to simulate");
    if (s.frames < 1) throw InputError(format("frames must be at least 1 (got {})", s.frames));
    if (!(s.fps > 0.0) || !std::isfinite(s.fps)) throw InputError(format("fps must be positive (got {})", s.fps));
    if (s.substeps < 1) throw InputError(format("substeps must be at least 1 (got {})", s.substeps));
    if (s.solverIterations < 1) throw InputError("solver iterations must be at least 1");
    if (!(s.strength >= 0.0)) throw InputError(format("strength must not be negative (got {})", s.strength));
    if (!(s.strengthVariation >= 0.0 && s.strengthVariation < 1.0))
        throw InputError("strength variation must be in [0, 1)");
    if (s.hullVertices < 4) throw InputError(format("hull vertices must be at least 4 (got {})", s.hullVertices));
    if (!(s.margin > 0.0)) throw InputError("the collision margin must be positive");
    if (!(s.triggerTime >= 0.0)) throw InputError("the trigger time must not be negative");
    if (s.projectile) {
        const Projectile& p = *s.projectile;
        if (!(p.mass > 0.0) || !(p.speed >= 0.0) || !(p.radius > 0.0))
            throw InputError("the projectile needs a positive mass and radius and a non-negative speed");
        if (!(glm::length(p.direction) > 0.0)) throw InputError("the projectile direction must not be zero");
    }
    if (s.explosion && (!(s.explosion->radius > 0.0) || !(s.explosion->impulse >= 0.0)))
        throw InputError("the explosion needs a positive radius and a non-negative impulse");
    for (std::size_t i = 0; i < pieces.size(); ++i) {
        const RigidPiece& p = pieces[i];
        if (!(p.mass > 0.0) || !std::isfinite(p.mass))
            throw InputError(format("piece {} ({}) has mass {}; it must be positive", i, p.name, p.mass));
        if (p.mesh.positions.empty()) throw InputError(format("piece {} ({}) has no vertices", i, p.name));
    }
    for (std::size_t i = 0; i < bonds.size(); ++i)
        if (bonds[i].a >= pieces.size() || bonds[i].b >= pieces.size() || bonds[i].a == bonds[i].b)
            throw InputError(format("bond {} joins pieces {} and {}, but there are {} pieces", i, bonds[i].a,
                                    bonds[i].b, pieces.size()));
}

// The principal frames and collision hulls of the pieces (built in parallel, each piece
// on its own) and the bounds of their rest pose.
struct PieceShapes {
    std::vector<PrincipalInertia> principal;
    std::vector<Hull> hulls;
    glm::dvec3 lo{std::numeric_limits<double>::max()}, hi{-std::numeric_limits<double>::max()};
};

PieceShapes pieceShapes(std::span<const RigidPiece> pieces, const SimulationSettings& settings) {
    const std::size_t n = pieces.size();
    PieceShapes shapes;
    shapes.principal.resize(n);
    shapes.hulls.resize(n);
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
        shapes.principal[i] = principalInertia(pieces[i].inertia);
        shapes.hulls[i] = buildHull(pieces[i], shapes.principal[i].axes, settings.hullVertices, settings.margin);
    });
    for (const RigidPiece& p : pieces)
        for (const glm::vec3& v : p.mesh.positions) {
            shapes.lo = glm::min(shapes.lo, p.centerOfMass + glm::dvec3(v));
            shapes.hi = glm::max(shapes.hi, p.centerOfMass + glm::dvec3(v));
        }
    return shapes;
}

// Swept-sphere CCD size for a piece: half its smallest hull extent, so small fast pieces
// do not tunnel through the ground.
double ccdSize(const Hull& hull) {
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const btVector3& v : hull.points) {
        lo = glm::min(lo, toGlm(v));
        hi = glm::max(hi, toGlm(v));
    }
    return std::max(1e-3, 0.5 * std::min({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}));
}

NodeLoads zeroLoads(std::size_t n) { return {std::vector<glm::dvec3>(n, glm::dvec3(0.0)), std::vector<glm::dvec3>(n, glm::dvec3(0.0))}; }

// Glue: one fixed joint per bond, anchored at the shared face's centroid, holds the pieces
// together. Whether a bond breaks is not read from the joint: a rigid solver's split of a
// load over redundant joints is arbitrary and swings whenever it re-solves (bond_stress.hpp).
// Once a frame, the bond graph's linear model gives each bond's largest principal stress
// under the pieces' weights and each piece's largest contact load of the frame's substeps
// (a hit lasts one substep: averaged over the frame it would count a quarter); the bond
// breaks when that exceeds what it carried in the first frame by more than its strength.
// Pieces of one glued cluster do not collide (ClusterDispatcher); once a break splits the
// cluster, they do.
struct Glue {
    double strength = 0.0;    // Pa, with this bond's variation
    double restStress = 0.0;  // Pa, what the bond carried in the first step
};

// One run of simulate(). Bullet's results depend on the order of every call that
// reaches it, so run() keeps one: pieces in piece order, glue in bond order, ground,
// colliders, then fixed steps (the projectile, if any, is added at the trigger step).
class Simulation {
public:
    Simulation(std::span<const RigidPiece> pieces, std::span<const Bond> bonds, const SimulationSettings& settings,
               const PieceShapes& shapes);
    SimulationResult run(const ProgressFn& progress);

private:
    void addPieces();
    void addGlue();
    void addGroundAndColliders();
    void buildWorld();
    void trigger();
    void collapse();
    void explode();
    void launchProjectile();
    void step();
    void advanceFrame();
    void record(int frame);
    void recordTurns(int frame);

    btRigidBody& addBody(std::unique_ptr<btRigidBody> body, std::unique_ptr<btCollisionShape> shape);
    void buildStressModel();
    void addContactLoads();
    void updateClusters();
    void breakOverloadedGlue();
    double totalEnergy() const;
    glm::dquat meshOrientation(std::size_t i) const;

    std::span<const RigidPiece> pieces_;
    std::span<const Bond> bonds_;
    const SimulationSettings& settings_;
    const std::size_t n_;
    const double dt_;          // one substep
    const long triggerStep_;   // the substep after which the trigger fires (0: before the first)
    const PieceShapes& shapes_;
    World w_;
    SimulationResult result_;
    std::vector<BodyInfo> info_;            // per piece
    std::vector<Glue> glue_;                // per bond, when there is glue
    std::unique_ptr<BondStressModel> stress_;  // built after the first frame, when there is glue
    NodeLoads frameLoads_;                     // per piece, when there is glue: its largest contact load of the frame so far
    btRigidBody* projectile_ = nullptr;
    BodyInfo projectileInfo_;
    long step_ = 0;
    // Turns along the path: each substep's rotation (always far below half a turn) is
    // added up, following the quaternion continuously from the last recorded one, so a
    // piece spinning more than half a turn per frame is told apart from one turning back.
    std::vector<glm::dquat> recorded_;  // the orientations written for the last frame
    std::vector<glm::dquat> path_;
    std::vector<double> travelled_;
};

Simulation::Simulation(std::span<const RigidPiece> pieces, std::span<const Bond> bonds,
                       const SimulationSettings& settings, const PieceShapes& shapes)
    : pieces_(pieces), bonds_(bonds), settings_(settings), n_(pieces.size()),
      dt_(1.0 / settings.fps / settings.substeps),
      triggerStep_(std::lround(std::ceil(settings.triggerTime / dt_ - 1e-9))), shapes_(shapes),
      recorded_(n_), path_(n_), travelled_(n_) {
    w_.world->setGravity(bt(settings_.gravity));
    btContactSolverInfo& solverInfo = w_.world->getSolverInfo();
    solverInfo.m_numIterations = settings_.solverIterations;
    solverInfo.m_solverMode &= ~SOLVER_RANDMIZE_ORDER;
    solverInfo.m_splitImpulse = 1;

    result_.frames = settings_.frames;
    result_.fps = settings_.fps;
    result_.pieces = n_;
    result_.groundHeight = settings_.groundHeight.value_or(shapes_.lo.y);
}

// Pieces in piece order, glue in bond order, then the ground and colliders.
void Simulation::buildWorld() {
    addPieces();
    addGlue();
    updateClusters();
    addGroundAndColliders();
}

SimulationResult Simulation::run(const ProgressFn& progress) {
    result_.transforms.resize(std::size_t(settings_.frames) * n_ * 7);
    result_.turns.assign(std::size_t(settings_.frames) * n_, 0.0f);
    buildWorld();
    if (triggerStep_ == 0) trigger();
    record(0);
    for (int frame = 1; frame < settings_.frames; ++frame) {
        advanceFrame();
        record(frame);
        recordTurns(frame);
        if (!progress(double(frame) / double(settings_.frames - 1))) throw Cancelled();
    }
    for (const auto& c : w_.constraints)
        if (!c->isEnabled()) ++result_.brokenBonds;
    return std::move(result_);
}

// Adds a body to the world and keeps it and its shape alive with it.
btRigidBody& Simulation::addBody(std::unique_ptr<btRigidBody> body, std::unique_ptr<btCollisionShape> shape) {
    w_.world->addRigidBody(body.get());
    w_.shapes.push_back(std::move(shape));
    w_.bodies.push_back(std::move(body));
    return *w_.bodies.back();
}

// One body per piece, in its principal frame; the body's user index is its piece.
void Simulation::addPieces() {
    for (std::size_t i = 0; i < n_; ++i) {
        const RigidPiece& p = pieces_[i];
        const PrincipalInertia& pi = shapes_.principal[i];
        const Hull& hull = shapes_.hulls[i];
        for (int c = 0; c < 3; ++c)
            if (!(pi.moments[c] > 0.0) || !std::isfinite(pi.moments[c]))
                throw InputError(format("piece {} ({}) has an inertia tensor that is not positive definite", i, p.name));
        auto shape = std::make_unique<btConvexHullShape>(&hull.points[0].x(), int(hull.points.size()),
                                                         int(sizeof(btVector3)));
        shape->setMargin(hull.margin);
        result_.hullVertices.push_back(int(hull.points.size()));
        const glm::dquat frame = glm::quat_cast(pi.axes);
        btRigidBody::btRigidBodyConstructionInfo ci(btScalar(p.mass), nullptr, shape.get(), bt(pi.moments));
        ci.m_startWorldTransform = btTransform(bt(frame), bt(p.centerOfMass));
        ci.m_friction = btScalar(settings_.friction);
        ci.m_restitution = btScalar(settings_.restitution);
        ci.m_linearDamping = btScalar(settings_.linearDamping);
        ci.m_angularDamping = btScalar(settings_.angularDamping);
        auto body = std::make_unique<btRigidBody>(ci);
        body->setUserIndex(int(i));
        const double small = ccdSize(hull);
        body->setCcdMotionThreshold(btScalar(0.5 * small));
        body->setCcdSweptSphereRadius(btScalar(0.8 * small));
        addBody(std::move(body), std::move(shape));
        info_.push_back({glm::conjugate(frame), pi.moments, p.mass});
    }
}

void Simulation::addGlue() {
    if (!(settings_.strength > 0.0)) return;
    for (std::size_t i = 0; i < bonds_.size(); ++i) {
        const Bond& b = bonds_[i];
        btRigidBody& A = *w_.bodies[b.a];
        btRigidBody& B = *w_.bodies[b.b];
        const btTransform anchor(btQuaternion::getIdentity(), bt(b.centroid));
        const btTransform inA = A.getCenterOfMassTransform().inverse() * anchor;
        const btTransform inB = B.getCenterOfMassTransform().inverse() * anchor;
        auto joint = std::make_unique<btFixedConstraint>(A, B, inA, inB);
        Rng rng(deriveSeed(settings_.seed, "bond-strength", i));
        const double variation = 1.0 + settings_.strengthVariation * (2.0 * rng.uniform() - 1.0);
        const double strength = b.strength > 0.0 ? b.strength : settings_.strength;  // the bond's material's, if it has one
        glue_.push_back({strength * variation, 0.0});
        w_.world->addConstraint(joint.get(), true);
        w_.constraints.push_back(std::move(joint));
    }
    if (!glue_.empty()) frameLoads_ = zeroLoads(n_);
    result_.bonds = w_.constraints.size();
}

void Simulation::addGroundAndColliders() {
    if (settings_.ground) {
        auto plane = std::make_unique<btStaticPlaneShape>(btVector3(0, 1, 0), btScalar(result_.groundHeight));
        btRigidBody::btRigidBodyConstructionInfo ci(0, nullptr, plane.get());
        ci.m_friction = btScalar(settings_.friction);
        ci.m_restitution = btScalar(settings_.restitution);
        addBody(std::make_unique<btRigidBody>(ci), std::move(plane));
    }
    if (settings_.support) {
        const Support& s = *settings_.support;
        auto plane = std::make_unique<btStaticPlaneShape>(btVector3(0, 1, 0), btScalar(s.height));
        btRigidBody::btRigidBodyConstructionInfo ci(0, nullptr, plane.get());
        ci.m_friction = btScalar(settings_.friction);
        ci.m_restitution = btScalar(settings_.restitution);
        addBody(std::make_unique<btRigidBody>(ci), std::move(plane)).setUserIndex(kSupport);
        w_.dispatcher.support = s;
    }
    for (const Mesh& m : settings_.colliders) {
        if (m.indices.empty()) continue;  // Bullet's BVH builder crashes on an empty mesh
        auto& vertices = w_.colliderVertices.emplace_back();
        auto& indices = w_.colliderIndices.emplace_back(m.indices.begin(), m.indices.end());
        for (const glm::vec3& v : m.positions) vertices.insert(vertices.end(), {v.x, v.y, v.z});
        auto array = std::make_unique<btTriangleIndexVertexArray>(int(indices.size() / 3), indices.data(),
                                                                  int(3 * sizeof(int)), int(m.positions.size()),
                                                                  vertices.data(), int(3 * sizeof(btScalar)));
        auto shape = std::make_unique<btBvhTriangleMeshShape>(array.get(), true);
        btRigidBody::btRigidBodyConstructionInfo ci(0, nullptr, shape.get());
        ci.m_friction = btScalar(settings_.friction);
        w_.triangleArrays.push_back(std::move(array));
        addBody(std::make_unique<btRigidBody>(ci), std::move(shape)).setUserIndex(kCollider);
    }
}

void Simulation::trigger() {
    if (settings_.collapse) collapse();
    if (settings_.explosion) explode();
    if (settings_.projectile) launchProjectile();
}

// Every bond breaks at once.
void Simulation::collapse() {
    for (auto& c : w_.constraints) c->setEnabled(false);
    for (std::size_t i = 0; stress_ && i < glue_.size(); ++i) stress_->breakLink(i);
    for (std::size_t i = 0; i < n_; ++i) w_.bodies[i]->activate(true);
    updateClusters();
}

void Simulation::explode() {
    const Explosion& x = *settings_.explosion;
    const double before = totalEnergy();
    for (std::size_t i = 0; i < n_; ++i) {
        const glm::dvec3 d = pieces_[i].centerOfMass - x.center;
        const double dist = glm::length(d);
        if (dist >= x.radius) continue;
        const double falloff = (1.0 - dist / x.radius) * (1.0 - dist / x.radius);
        const glm::dvec3 dir = dist > 1e-9 ? d / dist : glm::dvec3(0.0, 1.0, 0.0);
        w_.bodies[i]->activate(true);
        w_.bodies[i]->applyCentralImpulse(bt(dir * (x.impulse * falloff)));
    }
    result_.injectedEnergy += totalEnergy() - before;
}

void Simulation::launchProjectile() {
    const Projectile& p = *settings_.projectile;
    const glm::dvec3 dir = glm::normalize(p.direction);
    // Back from the target along the direction until outside the pieces' bounds.
    double exit = std::numeric_limits<double>::max();
    for (int a = 0; a < 3; ++a) {
        if (dir[a] > 1e-12) exit = std::min(exit, (p.target[a] - shapes_.lo[a]) / dir[a]);
        if (dir[a] < -1e-12) exit = std::min(exit, (shapes_.hi[a] - p.target[a]) / -dir[a]);
    }
    const glm::dvec3 start = p.target - dir * (std::max(0.0, exit) + p.radius + 0.05);
    auto shape = std::make_unique<btSphereShape>(btScalar(p.radius));
    const double moment = 0.4 * p.mass * p.radius * p.radius;
    btRigidBody::btRigidBodyConstructionInfo ci(btScalar(p.mass), nullptr, shape.get(),
                                                btVector3(btScalar(moment), btScalar(moment), btScalar(moment)));
    ci.m_startWorldTransform = btTransform(btQuaternion::getIdentity(), bt(start));
    ci.m_friction = btScalar(settings_.friction);
    ci.m_restitution = btScalar(settings_.restitution);
    auto body = std::make_unique<btRigidBody>(ci);
    body->setLinearVelocity(bt(dir * p.speed));
    body->setCcdMotionThreshold(btScalar(0.5 * p.radius));
    body->setCcdSweptSphereRadius(btScalar(0.9 * p.radius));
    projectile_ = &addBody(std::move(body), std::move(shape));
    projectileInfo_ = {glm::dquat(1.0, 0.0, 0.0, 0.0), glm::dvec3(moment), p.mass};
    result_.injectedEnergy += energyOf(*projectile_, projectileInfo_, settings_.gravity);
}

// One fixed Bullet step, then the glue check, then the trigger when it is due.
void Simulation::step() {
    w_.dispatcher.dropStaleContacts();
    w_.world->stepSimulation(btScalar(dt_), 0, btScalar(dt_));
    if (!glue_.empty()) addContactLoads();
    ++step_;
    if (step_ % settings_.substeps == 0) breakOverloadedGlue();
    if (step_ == triggerStep_) trigger();
}

// One frame's substeps, following each piece's turns from the last recorded orientation.
void Simulation::advanceFrame() {
    for (std::size_t i = 0; i < n_; ++i) {
        path_[i] = recorded_[i];
        travelled_[i] = 0.0;
    }
    for (int s = 0; s < settings_.substeps; ++s) {
        step();
        for (std::size_t i = 0; i < n_; ++i) {
            glm::dquat q = meshOrientation(i);
            const double d = glm::dot(q, path_[i]);
            if (d < 0.0) q = -q;
            travelled_[i] += 2.0 * std::acos(std::min(1.0, std::abs(d)));
            path_[i] = q;
        }
    }
}

void Simulation::record(int frame) {
    float* out = result_.transforms.data() + std::size_t(frame) * n_ * 7;
    for (std::size_t i = 0; i < n_; ++i, out += 7) {
        const btRigidBody& body = *w_.bodies[i];
        const glm::dvec3 x = frame == 0 ? pieces_[i].centerOfMass : toGlm(body.getCenterOfMassPosition());
        glm::dquat q = frame == 0 ? glm::dquat(1.0, 0.0, 0.0, 0.0) : meshOrientation(i);
        if (q.w < 0.0) q = -q;  // one sign per orientation: w ≥ 0
        recorded_[i] = q;
        const std::array<double, 7> values{x.x, x.y, x.z, q.x, q.y, q.z, q.w};
        for (int c = 0; c < 7; ++c) {
            if (!std::isfinite(values[std::size_t(c)]))
                throw std::runtime_error(format("simulate(): piece {} is not finite at frame {}", i, frame));
            out[c] = float(values[std::size_t(c)]);
        }
        result_.maxSpeed = std::max(result_.maxSpeed, double(body.getLinearVelocity().length()));
    }
    result_.energy.push_back(totalEnergy() - result_.injectedEnergy);
}

// The turns from frame - 1 to `frame`, negative when the path ends at the negated
// orientation of what record() wrote.
void Simulation::recordTurns(int frame) {
    for (std::size_t i = 0; i < n_; ++i) {
        const double turns = travelled_[i] / glm::two_pi<double>();
        result_.turns[std::size_t(frame - 1) * n_ + i] = float(glm::dot(path_[i], recorded_[i]) < 0.0 ? -turns : turns);
    }
}

// The model of the bond graph at rest: pieces at their rest centres of mass, held where the
// first step found them touching the ground, a support or a collider.
void Simulation::buildStressModel() {
    std::vector<StressNode> nodes(n_);
    for (std::size_t i = 0; i < n_; ++i) nodes[i] = {pieces_[i].centerOfMass, pieces_[i].mass, false};
    for (int m = 0; m < w_.dispatcher.getNumManifolds(); ++m) {
        const btPersistentManifold* manifold = w_.dispatcher.getManifoldByIndexInternal(m);
        const int i = manifold->getBody0()->getUserIndex(), j = manifold->getBody1()->getUserIndex();
        if (manifold->getNumContacts() == 0 || (i >= 0) == (j >= 0)) continue;
        nodes[std::size_t(std::max(i, j))].held = true;
    }
    std::vector<StressLink> links;
    links.reserve(bonds_.size());
    for (const Bond& b : bonds_) links.push_back({b.a, b.b, b.centroid, b.normal, std::max(b.area, 1e-8)});
    stress_ = std::make_unique<BondStressModel>(std::move(nodes), std::move(links));
    for (std::size_t i = 0; i < glue_.size(); ++i)
        if (!w_.constraints[i]->isEnabled()) stress_->breakLink(i);  // a collapse before the first step
}

// The contact impulses of the substep just taken, over its length, as forces and torques in
// each piece's rest frame; each piece keeps the largest of the frame's substeps.
void Simulation::addContactLoads() {
    NodeLoads step = zeroLoads(n_);
    const auto add = [&](int piece, const btVector3& impulse, const btVector3& at) {
        if (piece < 0) return;
        const btRigidBody& body = *w_.bodies[std::size_t(piece)];
        const glm::dquat back = glm::conjugate(meshOrientation(std::size_t(piece)));
        step.force[std::size_t(piece)] += back * toGlm(impulse) / dt_;
        step.torque[std::size_t(piece)] += back * toGlm((at - body.getCenterOfMassPosition()).cross(impulse)) / dt_;
    };
    for (int m = 0; m < w_.dispatcher.getNumManifolds(); ++m) {
        const btPersistentManifold* manifold = w_.dispatcher.getManifoldByIndexInternal(m);
        const int a = manifold->getBody0()->getUserIndex(), b = manifold->getBody1()->getUserIndex();
        for (int c = 0; c < manifold->getNumContacts(); ++c) {
            const btManifoldPoint& p = manifold->getContactPoint(c);
            const btVector3 impulse = p.m_normalWorldOnB * p.getAppliedImpulse() +
                                      p.m_lateralFrictionDir1 * p.m_appliedImpulseLateral1 +
                                      p.m_lateralFrictionDir2 * p.m_appliedImpulseLateral2;
            add(a, impulse, p.getPositionWorldOnA());
            add(b, -impulse, p.getPositionWorldOnB());
        }
    }
    for (std::size_t i = 0; i < n_; ++i)
        if (glm::length(step.force[i]) > glm::length(frameLoads_.force[i]))
            frameLoads_.force[i] = step.force[i], frameLoads_.torque[i] = step.torque[i];
}

// Clusters: connected components of the unbroken bonds (union-find, smallest index as
// the representative, so the labels depend on the bonds alone).
void Simulation::updateClusters() {
    UnionFind clusters(n_);
    for (std::size_t i = 0; i < glue_.size(); ++i)
        if (w_.constraints[i]->isEnabled()) clusters.unite(bonds_[i].a, bonds_[i].b);
    std::vector<int>& label = w_.dispatcher.cluster;
    label.resize(n_);
    for (std::size_t i = 0; i < n_; ++i) label[i] = int(clusters.find(std::uint32_t(i)));
}

void Simulation::breakOverloadedGlue() {
    if (glue_.empty()) return;
    const bool first = !stress_;
    if (first) buildStressModel();
    for (std::size_t i = 0; i < n_; ++i)  // the weights, in the rest frames
        frameLoads_.force[i] += glm::conjugate(meshOrientation(i)) * (pieces_[i].mass * settings_.gravity);
    const std::vector<double> stress = stress_->stresses(frameLoads_);
    std::fill(frameLoads_.force.begin(), frameLoads_.force.end(), glm::dvec3(0.0));
    std::fill(frameLoads_.torque.begin(), frameLoads_.torque.end(), glm::dvec3(0.0));
    bool broke = false;
    for (std::size_t i = 0; i < glue_.size(); ++i) {
        if (first) glue_[i].restStress = stress[i];
        btTypedConstraint& joint = *w_.constraints[i];
        if (!joint.isEnabled() || stress[i] - glue_[i].restStress <= glue_[i].strength) continue;
        stress_->breakLink(i);
        joint.setEnabled(false);
        joint.getRigidBodyA().activate(true);
        joint.getRigidBodyB().activate(true);
        broke = true;
    }
    if (broke) updateClusters();
}

double Simulation::totalEnergy() const {
    double e = 0.0;
    for (std::size_t i = 0; i < n_; ++i) e += energyOf(*w_.bodies[i], info_[i], settings_.gravity);
    if (projectile_) e += energyOf(*projectile_, projectileInfo_, settings_.gravity);
    return e;
}

// A piece's mesh orientation: its body's with the principal frame taken back out.
glm::dquat Simulation::meshOrientation(std::size_t i) const {
    return glm::normalize(toGlm(w_.bodies[i]->getCenterOfMassTransform().getRotation()) * info_[i].toMesh);
}

}  // namespace

std::vector<RigidPiece> rigidPieces(const FractureResult& fracture) {
    std::vector<RigidPiece> out;
    out.reserve(fracture.pieces.size());
    for (const FracturePiece& p : fracture.pieces)
        out.push_back({p.name, p.mesh, p.mass.mass, p.mass.centerOfMass, p.mass.inertia});
    return out;
}

PrincipalInertia principalInertia(const glm::dmat3& inertia) {
    // Cyclic Jacobi on the symmetric part; converges quadratically for 3×3.
    double a[3][3];
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) a[r][c] = 0.5 * (inertia[c][r] + inertia[r][c]);
    double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int sweep = 0; sweep < 50; ++sweep) {
        const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        const double scale = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if (off <= 1e-30 * scale || off == 0.0) break;
        for (int p = 0; p < 2; ++p)
            for (int q = p + 1; q < 3; ++q) {
                if (a[p][q] == 0.0) continue;
                const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
                const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
                for (int k = 0; k < 3; ++k) {  // A ← A·J
                    const double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; ++k) {  // A ← Jᵀ·A
                    const double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; ++k) {  // V ← V·J
                    const double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
    }
    PrincipalInertia out;
    out.moments = {a[0][0], a[1][1], a[2][2]};
    for (int c = 0; c < 3; ++c) out.axes[c] = glm::dvec3(v[0][c], v[1][c], v[2][c]);
    if (glm::determinant(out.axes) < 0.0) out.axes[2] = -out.axes[2];
    return out;
}

SimulationResult simulate(std::span<const RigidPiece> pieces, std::span<const Bond> bonds,
                          const SimulationSettings& settings, const ProgressFn& progress) {
    checkSettings(pieces, bonds, settings);
    const PieceShapes shapes = pieceShapes(pieces, settings);
    // Bodies slower than Bullet's thresholds (0.8 m/s, 1 rad/s) for a second fall asleep
    // (Bullet's default is two): rubble at rest costs nothing. A library global, always
    // set to the same value here.
    gDeactivationTime = btScalar(1.0);
    Simulation simulation(pieces, bonds, settings, shapes);
    return simulation.run(progress);
}

}  // namespace dawnforge::sim

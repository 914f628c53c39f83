// Rigid-body destruction with Bullet 3.24 (with hull.cpp and debris_motion.cpp, the Bullet translation units).
//
// Determinism: one single-threaded btDiscreteDynamicsWorld, actors added in the order of
// their smallest piece (a split's too), a fixed step passed to stepSimulation with
// maxSubSteps = 0 (no time accumulator), the solver's order randomisation left off; a step
// taken again after a break starts from the bodies' saved states. Hulls are built in
// parallel but each depends on its piece alone.
#include <dawnforge/sim/rigidbody.hpp>

#include "bond_stress.hpp"
#include "damage.hpp"
#include "debris.hpp"
#include "hull.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/seed.hpp>
#include <dawnforge/core/union_find.hpp>

#include <btBulletDynamicsCommon.h>
#include <BulletCollision/CollisionDispatch/btCompoundCollisionAlgorithm.h>
#include <BulletCollision/CollisionDispatch/btCompoundCompoundCollisionAlgorithm.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpaPenetrationDepthSolver.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkPairDetector.h>
#include <BulletCollision/NarrowPhaseCollision/btPointCollector.h>
#include <BulletCollision/NarrowPhaseCollision/btVoronoiSimplexSolver.h>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/quaternion.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>

namespace dawnforge::sim {

namespace {

// Sleeping, with PhysX's defaults (a wake counter of 0.4 s; a mass-normalised kinetic energy
// of 0.005 J/kg, 0.1 m/s): a body slower than these for kSleepAfter stops being simulated until
// something touches it, so rubble at rest costs nothing. Bullet's own thresholds (0.8 m/s,
// 1 rad/s for 2 s) let a body creep 1.6 m and turn a third of a turn before it sleeps.
constexpr double kSleepAfter = 0.4;        // s
constexpr double kSleepSpeed = 0.1;        // m/s
constexpr double kSleepTurnSpeed = 0.2;    // rad/s

// User indices of bodies: an actor's is its index (>= 0); the others' say what they are.
constexpr int kStatic = -1;   // ground plane, projectile
constexpr int kSupport = -2;  // SimulationSettings::support
constexpr int kCollider = -3; // SimulationSettings::colliders

// Pairs of pieces whose hulls overlap at rest. A piece's convex hull covers its hollows (a roof
// shell's hull fills the attic, a wall's its windows), so its neighbours' hulls can lie deep
// inside it: such a pair never collides, or the first time they came apart the solver would
// push them out of each other (a 45 t roof shot up at 21 m/s, 13 MJ from nowhere). A hull
// shape's user index is its piece.
struct HullOverlaps {
    std::vector<std::uint64_t> pairs;  // (smaller piece << 32) | larger, ascending

    bool contains(int a, int b) const {
        if (a < 0 || b < 0 || a == b) return false;
        const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::uint64_t(std::max(a, b));
        return std::binary_search(pairs.begin(), pairs.end(), key);
    }
};

// Bullet asks a global function about each pair of a compound's children; it reads the running
// simulation's overlaps (one world per thread).
thread_local const HullOverlaps* tOverlaps = nullptr;

bool childrenCollide(const btCollisionShape* a, const btCollisionShape* b) {
    return !tOverlaps || !tOverlaps->contains(a->getUserIndex(), b->getUserIndex());
}

class SupportDispatcher : public btCollisionDispatcher {
public:
    using btCollisionDispatcher::btCollisionDispatcher;
    std::optional<Support> support;

    // Bullet asks again at every step for every overlapping pair, so this may change with
    // where the actors are.
    bool needsCollision(const btCollisionObject* a, const btCollisionObject* b) override {
        const int i = a->getUserIndex(), j = b->getUserIndex();
        if (!childrenCollide(a->getCollisionShape(), b->getCollisionShape())) return false;  // two lone pieces
        if (support && (i == kSupport || j == kSupport || i == kCollider || j == kCollider)) {
            const btCollisionObject* actor = i >= 0 ? a : j >= 0 ? b : nullptr;
            if (actor) {
                const bool over = overSupport(*support, actor->getWorldTransform().getOrigin());
                if (over != (i == kSupport || j == kSupport)) return false;  // the support holds it, or the colliders do
            }
        }
        return btCollisionDispatcher::needsCollision(a, b);
    }

    // Contacts of pairs that no longer collide (an actor that left the support, or came over
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

// Bullet keeps the contacts it predicts for fast bodies (CCD) in manifolds of its own until the
// next step, and removing a body leaves them pointing at it: an actor's body is removed only
// after they are released (the next step makes them again).
class DynamicsWorld : public btDiscreteDynamicsWorld {
public:
    using btDiscreteDynamicsWorld::btDiscreteDynamicsWorld;
    void removeActorBody(btRigidBody* body) {
        releasePredictiveContacts();
        removeRigidBody(body);
    }
};

// Everything Bullet needs alive while the world runs. Members are declared so that the
// world is destroyed first; the bodies are removed from it before that.
struct World {
    std::vector<std::unique_ptr<btConvexHullShape>> hulls;  // per piece
    std::vector<std::unique_ptr<btCollisionShape>> shapes;  // of the other bodies
    std::vector<std::unique_ptr<ColliderShape>> colliders;  // their triangle arrays (the shapes are in `shapes`)
    std::vector<std::unique_ptr<btRigidBody>> bodies;        // ground, support, colliders, projectile
    std::vector<std::unique_ptr<btCompoundShape>> compounds;  // per actor; null for a lone piece
    std::vector<std::unique_ptr<btRigidBody>> actors;         // per actor; null once it has split
    btDefaultCollisionConfiguration configuration;
    SupportDispatcher dispatcher{&configuration};
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    std::unique_ptr<DynamicsWorld> world = std::make_unique<DynamicsWorld>(&dispatcher, &broadphase, &solver, &configuration);

    ~World() {
        for (auto& b : actors)
            if (b) world->removeRigidBody(b.get());
        for (auto& b : bodies) world->removeRigidBody(b.get());
        world.reset();
    }
};

struct BodyInfo {
    glm::dvec3 moments{0.0};  // principal, in the body frame
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
    if (s.explosion && (!(s.explosion->radius > 0.0) || !(s.explosion->speed >= 0.0)))
        throw InputError("the explosion needs a positive radius and a non-negative speed");
    if (s.explosion && s.explosion->speed > kFastestThrow)
        throw InputError(format("the explosion's speed {} m/s is faster than {} m/s, the fastest a piece may be thrown",
                                s.explosion->speed, kFastestThrow));
    if (!(s.impactTime > 0.0) || !(s.damageHalfLife > 0.0))
        throw InputError("the impact time and the damage half-life must be positive");
    if (!(s.damageTransmission >= 0.0 && s.damageTransmission <= 1.0))
        throw InputError(format("the damage transmission must be in [0, 1] (got {})", s.damageTransmission));
    if (s.damageHops < 1) throw InputError(format("damage hops must be at least 1 (got {})", s.damageHops));
    const DebrisSettings& d = s.debris;
    if (!(d.chipsPerSquareMetre >= 0.0) || !std::isfinite(d.chipsPerSquareMetre) || d.maxChipsPerBond < 0 ||
        !(d.chipSize > 0.0) || !std::isfinite(d.chipSize) || !(d.spraySpeed >= 0.0) || !std::isfinite(d.spraySpeed))
        throw InputError("debris needs a non-negative chip rate, count and spray speed and a positive chip size");
    if (!(d.puffsPerSquareMetre >= 0.0) || !std::isfinite(d.puffsPerSquareMetre) || !(d.puffSize > 0.0) ||
        !std::isfinite(d.puffSize) || !(d.puffLife > 0.0) || !std::isfinite(d.puffLife))
        throw InputError("dust needs a non-negative puff rate and a positive puff size and life");
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

glm::dmat3 diagonal(const glm::dvec3& d) { return glm::dmat3(d.x, 0.0, 0.0, 0.0, d.y, 0.0, 0.0, 0.0, d.z); }

// What Bullet keeps of a moving body between steps, to take a step back.
struct BodyState {
    btRigidBody* body;
    btTransform transform, interpolation;
    btVector3 linear, angular;
    int activation;
    btScalar sleeping;
};

std::vector<BodyState> saveStates(std::span<const std::unique_ptr<btRigidBody>> actors, btRigidBody* projectile) {
    std::vector<BodyState> out;
    const auto save = [&](btRigidBody* b) {
        if (b && !b->isStaticObject())
            out.push_back({b, b->getCenterOfMassTransform(), b->getInterpolationWorldTransform(), b->getLinearVelocity(),
                           b->getAngularVelocity(), b->getActivationState(), b->getDeactivationTime()});
    };
    for (const auto& b : actors) save(b.get());
    save(projectile);
    return out;
}

void restoreStates(std::span<const BodyState> states) {
    for (const BodyState& s : states) {
        s.body->setCenterOfMassTransform(s.transform);
        s.body->setInterpolationWorldTransform(s.interpolation);
        s.body->setLinearVelocity(s.linear);
        s.body->setAngularVelocity(s.angular);
        s.body->setInterpolationLinearVelocity(s.linear);
        s.body->setInterpolationAngularVelocity(s.angular);
        s.body->forceActivationState(s.activation);
        s.body->setDeactivationTime(s.sleeping);
    }
}

// Glued pieces as compound actors (the model of NVIDIA Blast and Unreal's Chaos): each set of
// pieces connected by unbroken bonds is one rigid body, a compound of their hulls with their
// masses and inertias summed exactly; a set that rests on the ground or the support is fixed
// there. Nothing inside an actor is solved: no joints, no contacts between its pieces.
// After every substep the contacts on the pieces damage the bonds near them (damage.hpp); when
// bonds break, the substep is taken again from where it started, with the broken actors split
// into their new connected sets, each moving with the velocity field of its parent, so that
// what broke a bond pushes the pieces it freed instead of bouncing off the whole. Then the
// structure a break changed carries its weight in the bond graph's linear model
// (bond_stress.hpp), one round of breaks a substep: a bond whose stress exceeds what it carried
// at rest by more than its strength breaks, and the groups that changed are solved again in the
// next substep, so a breach's consequences spread from it over time.
constexpr double kFront = 0.5;

// A glued piece resting on the ground plane or the support is bonded to it (Blast's bond to
// the world): a link in the bond graph to a fixed node, as wide as the piece's faces that lie
// on the plane, as strong as the piece's strongest bond. While it holds, the piece holds its
// actor where it stands; a hit that shears it off frees the piece.
struct GroundLink {
    std::uint32_t piece = 0;
    glm::dvec3 point{0.0};  // the centroid of the faces on the plane
    double area = 0.0;      // m²
};

struct Glue {
    double strength = 0.0;    // Pa, with this bond's variation
    double restStress = 0.0;  // Pa, what the bond carries at rest under the weights
    bool broken = false;
};

struct Actor {
    std::vector<std::uint32_t> pieces;  // ascending; child k of the compound is pieces[k]
    BodyInfo info;                      // the whole set's mass and principal moments
    bool fixed = false;                 // held where it rests until a bond breaks
};

// A parent's velocity field, which the actors split from it inherit.
struct Motion {
    glm::dvec3 linear{0.0}, angular{0.0}, center{0.0};
};

// One run of simulate(). Bullet's results depend on the order of every call that
// reaches it, so run() keeps one: pieces' hulls in piece order, actors in the order of their
// smallest piece, ground, colliders, then fixed steps (the projectile, if any, is added at the
// trigger step); a split adds its actors in the same order.
class Simulation {
public:
    Simulation(std::span<const RigidPiece> pieces, std::span<const Bond> bonds, const SimulationSettings& settings,
               const PieceShapes& shapes);
    SimulationResult run(const ProgressFn& progress);

private:
    void addHulls();
    void addGlue();
    void addGroundLinks();
    bool held(std::uint32_t piece) const;
    std::pair<std::uint32_t, std::uint32_t> linkEnds(std::size_t link) const;
    void findHullOverlaps();
    void addActors();
    void addGroundAndColliders();
    void buildWorld();
    void trigger();
    void collapse();
    void explode();
    void launchProjectile();
    void sleepWhenSlow(btRigidBody& body) const;
    void limitSpin();
    void step();
    void advanceFrame();
    void record(int frame);
    void recordTurns(int frame);

    btRigidBody& addBody(std::unique_ptr<btRigidBody> body, std::unique_ptr<btCollisionShape> shape);
    std::uint32_t addActor(std::vector<std::uint32_t> members, std::span<const btTransform> frames, const Motion& parent,
                           bool parentFixed);
    void splitActors();
    std::vector<std::vector<std::uint32_t>> connectedSets() const;
    void buildStressModel();
    void buildDamageModel();
    void strikeGlue();
    bool breakStruckBonds();
    void breakLink(std::size_t link, double time);
    bool breakBonds(NodeLoads loads, std::vector<bool> active, int rounds);
    bool settleSupport();
    double totalEnergy() const;
    btTransform pieceFrame(std::size_t i) const;
    glm::dvec3 pieceVelocity(std::size_t i) const;
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
    std::vector<glm::dquat> toMesh_;        // per piece: its principal frame at rest, conjugated
    std::vector<btTransform> restFrames_;   // per piece: its principal frame at rest, in the world
    std::vector<GroundLink> ground_;        // the glued pieces that rest on the ground or the support
    std::vector<int> groundOf_;             // per piece: its ground link, or -1
    std::vector<Actor> actors_;             // every actor made, split ones too (their bodies are gone)
    std::vector<std::uint32_t> actorOf_;    // per piece
    std::vector<btTransform> local_;        // per piece: its principal frame in its actor's body frame
    std::vector<Glue> glue_;                // per bond, then per ground link, when there is glue
    HullOverlaps overlaps_;
    std::unique_ptr<BondStressModel> stress_;  // when there is glue
    std::unique_ptr<DamageModel> damage_;      // when there is glue
    std::vector<bool> unsettled_;              // per node of the bond graph: its group changed since it was last solved
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
      actorOf_(n_), local_(n_), recorded_(n_), path_(n_), travelled_(n_) {
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

// Hulls in piece order, glue in bond order, actors, then the ground and colliders.
void Simulation::buildWorld() {
    addHulls();
    addGlue();
    addGroundLinks();
    findHullOverlaps();
    addActors();
    buildStressModel();
    buildDamageModel();
    addGroundAndColliders();
}

SimulationResult Simulation::run(const ProgressFn& progress) {
    result_.transforms.resize(std::size_t(settings_.frames) * n_ * 7);
    result_.turns.assign(std::size_t(settings_.frames) * n_, 0.0f);
    tOverlaps = &overlaps_;
    struct Reset { ~Reset() { tOverlaps = nullptr; } } reset;
    buildWorld();
    if (triggerStep_ == 0) trigger();
    record(0);
    for (int frame = 1; frame < settings_.frames; ++frame) {
        advanceFrame();
        record(frame);
        recordTurns(frame);
        if (!progress(double(frame) / double(settings_.frames - 1))) throw Cancelled();
    }
    for (std::size_t i = 0; i < bonds_.size() && i < glue_.size(); ++i) result_.brokenBonds += glue_[i].broken;
    for (const Actor& a : actors_) result_.fixedActors += a.fixed;
    result_.actors = actors_.size();
    return std::move(result_);
}

// Adds a body that is not an actor to the world and keeps it and its shape alive with it.
btRigidBody& Simulation::addBody(std::unique_ptr<btRigidBody> body, std::unique_ptr<btCollisionShape> shape) {
    w_.world->addRigidBody(body.get());
    w_.shapes.push_back(std::move(shape));
    w_.bodies.push_back(std::move(body));
    return *w_.bodies.back();
}

// Each piece's hull, in its principal frame.
void Simulation::addHulls() {
    for (std::size_t i = 0; i < n_; ++i) {
        const PrincipalInertia& pi = shapes_.principal[i];
        const Hull& hull = shapes_.hulls[i];
        for (int c = 0; c < 3; ++c)
            if (!(pi.moments[c] > 0.0) || !std::isfinite(pi.moments[c]))
                throw InputError(format("piece {} ({}) has an inertia tensor that is not positive definite", i,
                                        pieces_[i].name));
        auto shape = std::make_unique<btConvexHullShape>(&hull.points[0].x(), int(hull.points.size()),
                                                         int(sizeof(btVector3)));
        shape->setMargin(hull.margin);
        shape->setUserIndex(int(i));
        w_.hulls.push_back(std::move(shape));
        result_.hullVertices.push_back(int(hull.points.size()));
        toMesh_.push_back(glm::conjugate(glm::quat_cast(pi.axes)));
        restFrames_.emplace_back(bt(glm::quat_cast(pi.axes)), bt(pieces_[i].centerOfMass));
    }
}

void Simulation::addGlue() {
    if (!(settings_.strength > 0.0)) return;
    for (std::size_t i = 0; i < bonds_.size(); ++i) {
        Rng rng(deriveSeed(settings_.seed, "bond-strength", i));
        const double variation = 1.0 + settings_.strengthVariation * (2.0 * rng.uniform() - 1.0);
        const double strength = bonds_[i].strength > 0.0 ? bonds_[i].strength : settings_.strength;  // the bond's material's, if it has one
        glue_.push_back({strength * variation, 0.0, false});
    }
    result_.bonds = glue_.size();
}

// The glued pieces whose lowest point is within the collision margin of the ground plane, or
// of the support they stand over, get a ground link (appended to the glue, after the bonds).
// Its area is that of their faces within the margin of the plane (a point or an edge on it
// counts a square centimetre).
void Simulation::addGroundLinks() {
    groundOf_.assign(n_, -1);
    if (glue_.empty()) return;
    std::vector<double> strongest(n_, 0.0);
    for (std::size_t i = 0; i < bonds_.size(); ++i)
        for (std::uint32_t p : {bonds_[i].a, bonds_[i].b}) strongest[p] = std::max(strongest[p], glue_[i].strength);
    for (std::uint32_t i = 0; i < n_; ++i) {
        const RigidPiece& p = pieces_[i];
        const glm::dvec3& c = p.centerOfMass;
        double lowest = std::numeric_limits<double>::max();
        for (const glm::vec3& v : p.mesh.positions) lowest = std::min(lowest, c.y + double(v.y));
        std::optional<double> plane;
        if (settings_.ground && lowest - settings_.margin <= result_.groundHeight) plane = result_.groundHeight;
        if (const std::optional<Support>& s = settings_.support;
            s && c.x >= s->min.x && c.x <= s->max.x && c.z >= s->min.y && c.z <= s->max.y && lowest - settings_.margin <= s->height)
            plane = s->height;
        if (!plane || !(strongest[i] > 0.0)) continue;
        GroundLink link{i, glm::dvec3(0.0), 0.0};
        const auto on = [&](std::uint32_t v) { return c.y + double(p.mesh.positions[v].y) <= *plane + settings_.margin; };
        for (std::size_t t = 0; t + 2 < p.mesh.indices.size(); t += 3) {
            const std::uint32_t* v = &p.mesh.indices[t];
            if (!on(v[0]) || !on(v[1]) || !on(v[2])) continue;
            const glm::dvec3 a(p.mesh.positions[v[0]]), b(p.mesh.positions[v[1]]), d(p.mesh.positions[v[2]]);
            const double area = 0.5 * glm::length(glm::cross(b - a, d - a));
            link.area += area;
            link.point += area * (c + (a + b + d) / 3.0);
        }
        if (link.area > 1e-4) {
            link.point /= link.area;
        } else {
            link = {i, glm::dvec3(c.x, lowest, c.z), 1e-4};
        }
        groundOf_[i] = int(ground_.size());
        ground_.push_back(link);
        glue_.push_back({strongest[i], 0.0, false});
    }
}

// A piece is held while its ground link is.
bool Simulation::held(std::uint32_t piece) const {
    return groundOf_[piece] >= 0 && !glue_[bonds_.size() + std::size_t(groundOf_[piece])].broken;
}

// A link's two nodes: a bond's pieces, or a ground link's piece and the ground (node n).
std::pair<std::uint32_t, std::uint32_t> Simulation::linkEnds(std::size_t link) const {
    if (link < bonds_.size()) return {bonds_[link].a, bonds_[link].b};
    return {ground_[link - bonds_.size()].piece, std::uint32_t(n_)};
}

// The sets of pieces joined by unbroken bonds, each ascending, ordered by their first piece.
std::vector<std::vector<std::uint32_t>> Simulation::connectedSets() const {
    UnionFind sets(n_);
    for (std::size_t i = 0; i < bonds_.size() && i < glue_.size(); ++i)
        if (!glue_[i].broken) sets.unite(bonds_[i].a, bonds_[i].b);
    std::vector<std::vector<std::uint32_t>> out;
    std::vector<std::uint32_t> index(n_, std::numeric_limits<std::uint32_t>::max());
    for (std::uint32_t i = 0; i < n_; ++i) {
        const std::uint32_t root = sets.find(i);
        if (index[root] == std::numeric_limits<std::uint32_t>::max()) index[root] = std::uint32_t(out.size()), out.emplace_back();
        out[index[root]].push_back(i);
    }
    return out;
}

// Candidates by their hulls' bounds at rest (sorted along x), then GJK and EPA on each: a pair
// is kept when its hulls, margins included, overlap by more than two margins (neighbours that
// share a face touch, or overlap by the rounding of their hulls).
void Simulation::findHullOverlaps() {
    std::vector<btVector3> lo(n_), hi(n_);
    for (std::size_t i = 0; i < n_; ++i) w_.hulls[i]->getAabb(restFrames_[i], lo[i], hi[i]);
    std::vector<std::uint32_t> order(n_);
    for (std::uint32_t i = 0; i < n_; ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
        return lo[a].x() < lo[b].x() || (lo[a].x() == lo[b].x() && a < b);
    });
    std::vector<std::vector<std::uint64_t>> found(n_);
    tbb::parallel_for(std::size_t(0), n_, [&](std::size_t k) {
        const std::uint32_t a = order[k];
        for (std::size_t m = k + 1; m < n_ && lo[order[m]].x() <= hi[a].x(); ++m) {
            const std::uint32_t b = order[m];
            if (lo[b].y() > hi[a].y() || hi[b].y() < lo[a].y() || lo[b].z() > hi[a].z() || hi[b].z() < lo[a].z()) continue;
            btVoronoiSimplexSolver simplex;
            btGjkEpaPenetrationDepthSolver epa;
            btGjkPairDetector gjk(w_.hulls[a].get(), w_.hulls[b].get(), &simplex, &epa);
            btGjkPairDetector::ClosestPointInput input;
            input.m_transformA = restFrames_[a];
            input.m_transformB = restFrames_[b];
            btPointCollector result;
            gjk.getClosestPoints(input, result, nullptr);
            if (result.m_hasResult && result.m_distance < -2.0 * settings_.margin)
                found[a].push_back((std::uint64_t(std::min(a, b)) << 32) | std::uint64_t(std::max(a, b)));
        }
    });
    for (const std::vector<std::uint64_t>& f : found) overlaps_.pairs.insert(overlaps_.pairs.end(), f.begin(), f.end());
    std::sort(overlaps_.pairs.begin(), overlaps_.pairs.end());
    result_.overlappingHulls = overlaps_.pairs.size();
}

void Simulation::addActors() {
    for (std::vector<std::uint32_t>& set : connectedSets()) addActor(std::move(set), restFrames_, Motion{}, true);
}

// One body for `members` (at `frames`, per piece, world): a lone piece is its hull, a set a
// compound of its hulls in its principal frame. A set with a held piece is fixed while its
// parent was; any other moves with its parent's velocity field.
std::uint32_t Simulation::addActor(std::vector<std::uint32_t> members, std::span<const btTransform> frames,
                                   const Motion& parent, bool parentFixed) {
    const std::uint32_t id = std::uint32_t(actors_.size());
    Actor& actor = actors_.emplace_back();
    actor.fixed = settings_.anchor && parentFixed && members.size() > 1 &&
                  std::any_of(members.begin(), members.end(), [&](std::uint32_t i) { return held(i); });
    glm::dvec3 center(0.0);
    for (std::uint32_t i : members) {
        actor.info.mass += pieces_[i].mass;
        center += pieces_[i].mass * toGlm(frames[i].getOrigin());
    }
    center /= actor.info.mass;
    glm::dmat3 inertia(0.0);
    for (std::uint32_t i : members) {
        const glm::dmat3 R = glm::mat3_cast(toGlm(frames[i].getRotation()));
        const glm::dvec3 d = toGlm(frames[i].getOrigin()) - center;
        inertia += R * diagonal(shapes_.principal[i].moments) * glm::transpose(R) +
                   pieces_[i].mass * (glm::dot(d, d) * glm::dmat3(1.0) - glm::outerProduct(d, d));
    }
    const PrincipalInertia principal = principalInertia(inertia);
    actor.info.moments = principal.moments;
    const btTransform frame = members.size() == 1 ? frames[members[0]]
                                                  : btTransform(bt(glm::quat_cast(principal.axes)), bt(center));
    btCollisionShape* shape = w_.hulls[members[0]].get();
    std::unique_ptr<btCompoundShape> compound;
    if (members.size() > 1) {
        compound = std::make_unique<btCompoundShape>(true, int(members.size()));
        for (std::uint32_t i : members) compound->addChildShape(frame.inverse() * frames[i], w_.hulls[i].get());
        shape = compound.get();
    }
    double ccd = std::numeric_limits<double>::max();
    for (std::uint32_t i : members) {
        actorOf_[i] = id;
        local_[i] = members.size() == 1 ? btTransform::getIdentity() : frame.inverse() * frames[i];
        ccd = std::min(ccd, ccdSize(shapes_.hulls[i]));
    }
    const double mass = actor.fixed ? 0.0 : actor.info.mass;
    btRigidBody::btRigidBodyConstructionInfo ci(btScalar(mass), nullptr, shape,
                                                actor.fixed ? btVector3(0, 0, 0) : bt(actor.info.moments));
    ci.m_startWorldTransform = frame;
    ci.m_friction = btScalar(settings_.friction);
    ci.m_restitution = btScalar(settings_.restitution);
    ci.m_linearDamping = btScalar(settings_.linearDamping);
    ci.m_angularDamping = btScalar(settings_.angularDamping);
    auto body = std::make_unique<btRigidBody>(ci);
    sleepWhenSlow(*body);
    body->setUserIndex(int(id));
    if (!actor.fixed) {
        body->setLinearVelocity(bt(parent.linear + glm::cross(parent.angular, center - parent.center)));
        body->setAngularVelocity(bt(parent.angular));
        body->setCcdMotionThreshold(btScalar(0.5 * ccd));
        body->setCcdSweptSphereRadius(btScalar(0.8 * ccd));
    }
    actor.pieces = std::move(members);
    w_.world->addRigidBody(body.get());
    w_.actors.push_back(std::move(body));
    w_.compounds.push_back(std::move(compound));
    return id;
}

// Actors whose pieces no longer form one connected set give way to one actor per set, and a
// fixed actor whose last ground link broke to one that moves.
void Simulation::splitActors() {
    const std::vector<std::vector<std::uint32_t>> sets = connectedSets();
    std::vector<std::uint32_t> setOf(n_);
    for (std::size_t s = 0; s < sets.size(); ++s)
        for (std::uint32_t i : sets[s]) setOf[i] = std::uint32_t(s);
    const std::size_t before = actors_.size();
    std::vector<btTransform> frames(n_);
    for (std::size_t a = 0; a < before; ++a) {
        const std::vector<std::uint32_t>& members = actors_[a].pieces;
        const bool whole = std::all_of(members.begin(), members.end(), [&](std::uint32_t i) { return setOf[i] == setOf[members[0]]; });
        const bool stillHeld = std::any_of(members.begin(), members.end(), [&](std::uint32_t i) { return held(i); });
        if (!w_.actors[a] || (whole && (stillHeld || !actors_[a].fixed))) continue;
        const btRigidBody& body = *w_.actors[a];
        const Motion parent{toGlm(body.getLinearVelocity()), toGlm(body.getAngularVelocity()), toGlm(body.getCenterOfMassPosition())};
        for (std::uint32_t i : members) frames[i] = pieceFrame(i);
        const bool fixed = actors_[a].fixed;
        const std::vector<std::uint32_t> pieces = members;  // addActor may move actors_
        w_.world->removeActorBody(w_.actors[a].get());
        w_.actors[a].reset();
        w_.compounds[a].reset();
        std::vector<bool> done(sets.size(), false);
        for (std::uint32_t i : pieces)
            if (!done[setOf[i]]) done[setOf[i]] = true, addActor(sets[setOf[i]], frames, parent, fixed);
    }
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
        std::unique_ptr<ColliderShape>& c = w_.colliders.emplace_back(colliderShape(m));
        btRigidBody::btRigidBodyConstructionInfo ci(0, nullptr, c->shape.get());
        ci.m_friction = btScalar(settings_.friction);
        addBody(std::make_unique<btRigidBody>(ci), std::move(c->shape)).setUserIndex(kCollider);
    }
}

void Simulation::trigger() {
    if (settings_.collapse) collapse();
    if (settings_.explosion) explode();
    if (settings_.projectile) launchProjectile();
}

// Every bond, and every ground link, breaks at once.
void Simulation::collapse() {
    for (std::size_t i = 0; i < glue_.size(); ++i)
        if (!glue_[i].broken) breakLink(i, double(step_) * dt_);
    splitActors();
}

// A bond or ground link breaks at `time`: the bond graph no longer has it, its ends' groups
// are unsettled, and a bond's break is recorded.
void Simulation::breakLink(std::size_t link, double time) {
    glue_[link].broken = true;
    stress_->breakLink(link);
    damage_->breakLink(link);
    const auto [a, b] = linkEnds(link);
    unsettled_[a] = unsettled_[b] = true;
    if (link < bonds_.size()) result_.breaks.push_back({link, time});
}

// The blast pushes each piece in proportion to the area it shows, (m / m̄)^(2/3) of what a piece
// of the mean mass gets (the same impulse on every piece shot slivers off at 20 km/s), and
// throws none faster than kFastestThrow. The impulses load the bond graph's linear model first
// (over one substep; a field of impulses on every piece is a load it splits as a body would),
// so that what they break is split before they push the pieces; a fixed actor takes what is left.
void Simulation::explode() {
    const Explosion& x = *settings_.explosion;
    const double before = totalEnergy();
    double mean = 0.0;
    for (const RigidPiece& p : pieces_) mean += p.mass / double(n_);
    std::vector<glm::dvec3> impulse(n_, glm::dvec3(0.0));
    for (std::size_t i = 0; i < n_; ++i) {
        const glm::dvec3 d = pieces_[i].centerOfMass - x.center;
        const double dist = glm::length(d);
        if (dist >= x.radius) continue;
        const double falloff = (1.0 - dist / x.radius) * (1.0 - dist / x.radius);
        double speed = x.speed * falloff * std::cbrt(mean / pieces_[i].mass);  // impulse ∝ (m / m̄)^(2/3)
        if (speed > kFastestThrow) speed = kFastestThrow, ++result_.clampedThrows;
        impulse[i] = (dist > 1e-9 ? d / dist : glm::dvec3(0.0, 1.0, 0.0)) * (pieces_[i].mass * speed);
    }
    if (stress_) {
        NodeLoads loads = zeroLoads(n_ + 1);
        for (std::size_t i = 0; i < n_; ++i) loads.force[i] = glm::conjugate(meshOrientation(i)) * impulse[i] / dt_;
        if (breakBonds(std::move(loads), std::vector<bool>(n_ + 1, true), std::numeric_limits<int>::max())) splitActors();
    }
    for (std::size_t i = 0; i < n_; ++i) {
        btRigidBody& body = *w_.actors[actorOf_[i]];
        if (impulse[i] == glm::dvec3(0.0) || body.isStaticObject()) continue;
        body.activate(true);
        body.applyImpulse(bt(impulse[i]), pieceFrame(i).getOrigin() - body.getCenterOfMassPosition());
    }
    result_.injectedEnergy += totalEnergy() - before;
}

void Simulation::sleepWhenSlow(btRigidBody& body) const {
    if (settings_.sleep)
        body.setSleepingThresholds(btScalar(kSleepSpeed), btScalar(kSleepTurnSpeed));
    else
        body.setActivationState(DISABLE_DEACTIVATION);
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
    sleepWhenSlow(*body);
    body->setLinearVelocity(bt(dir * p.speed));
    body->setCcdMotionThreshold(btScalar(0.5 * p.radius));
    body->setCcdSweptSphereRadius(btScalar(0.9 * p.radius));
    projectile_ = &addBody(std::move(body), std::move(shape));
    projectileInfo_ = {glm::dvec3(moment), p.mass};
    result_.injectedEnergy += energyOf(*projectile_, projectileInfo_, settings_.gravity);
}

// Bullet turns a body by at most an eighth of a turn per step, and past that its quaternion
// update is wrong (the axis is scaled by the clamped angle, and the body flips by up to half a
// turn each step): no body spins faster than that. A sliver that an explosion hits off its
// actor's centre would (78,794 rad/s on the elephant's).
void Simulation::limitSpin() {
    const double most = 0.9 * glm::quarter_pi<double>() / dt_;
    for (const auto& body : w_.actors) {
        if (!body || body->isStaticObject()) continue;
        const double spin = double(body->getAngularVelocity().length());
        if (spin > most) body->setAngularVelocity(body->getAngularVelocity() * btScalar(most / spin));
    }
}

// One round of the structures that the last step's breaks changed carrying their weights, then
// one fixed Bullet step; while its blows break bonds, it is taken again from where it started
// with the broken actors split (each retake breaks at least one more bond, so this ends). Then
// the trigger when it is due.
void Simulation::step() {
    std::vector<BodyState> start;
    std::vector<double> damage;
    limitSpin();
    if (settleSupport()) splitActors();
    for (;;) {
        w_.dispatcher.dropStaleContacts();
        if (damage_) start = saveStates(w_.actors, projectile_), damage = damage_->damages();
        w_.world->stepSimulation(btScalar(dt_), 0, btScalar(dt_));
        if (!breakStruckBonds()) break;
        restoreStates(start);
        damage_->restore(damage);
        splitActors();
    }
    ++step_;
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
        for (std::size_t i = 0; i < n_; ++i) travelled_[i] += followTurn(path_[i], meshOrientation(i));
    }
}

void Simulation::record(int frame) {
    float* out = result_.transforms.data() + std::size_t(frame) * n_ * 7;
    for (std::size_t i = 0; i < n_; ++i, out += 7) {
        const glm::dvec3 x = frame == 0 ? pieces_[i].centerOfMass : toGlm(pieceFrame(i).getOrigin());
        glm::dquat q = frame == 0 ? glm::dquat(1.0, 0.0, 0.0, 0.0) : meshOrientation(i);
        if (q.w < 0.0) q = -q;  // one sign per orientation: w ≥ 0
        recorded_[i] = q;
        const std::array<double, 7> values{x.x, x.y, x.z, q.x, q.y, q.z, q.w};
        for (int c = 0; c < 7; ++c) {
            if (!std::isfinite(values[std::size_t(c)]))
                throw std::runtime_error(format("simulate(): piece {} is not finite at frame {}", i, frame));
            out[c] = float(values[std::size_t(c)]);
        }
        result_.maxSpeed = std::max(result_.maxSpeed, glm::length(pieceVelocity(i)));
    }
    result_.energy.push_back(totalEnergy() - result_.injectedEnergy);
}

// The turns from frame - 1 to `frame`, negative when the path ends at the negated
// orientation of what record() wrote.
void Simulation::recordTurns(int frame) {
    for (std::size_t i = 0; i < n_; ++i)
        result_.turns[std::size_t(frame - 1) * n_ + i] = signedTurns(travelled_[i], path_[i], recorded_[i]);
}

// The model of the bond graph at rest: pieces at their rest centres of mass, the held ones
// fixed; what each bond carries under the weights alone is its rest stress.
void Simulation::buildStressModel() {
    if (glue_.empty()) return;
    std::vector<StressNode> nodes(n_ + 1);  // the pieces, then the ground
    for (std::size_t i = 0; i < n_; ++i) nodes[i] = {pieces_[i].centerOfMass, pieces_[i].mass, false, pieces_[i].inertia};
    nodes[n_] = {glm::dvec3(0.0), 0.0, true};
    std::vector<StressLink> links;
    links.reserve(glue_.size());
    // Each link as stiff as it is strong: a pane's or a partition's bonds, weak, are as much
    // softer, so they carry their share of the structure's deformation, not of its loads (with
    // one modulus, a breach's sag broke window bonds across a building 12 m from it).
    const auto modulus = [&](std::size_t i) { return glue_[i].strength / settings_.strength; };
    for (const Bond& b : bonds_) links.push_back({b.a, b.b, b.centroid, b.normal, std::max(b.area, 1e-8), modulus(links.size())});
    for (const GroundLink& g : ground_)
        links.push_back({g.piece, std::uint32_t(n_), g.point, {0.0, -1.0, 0.0}, g.area, modulus(links.size())});
    stress_ = std::make_unique<BondStressModel>(std::move(nodes), std::move(links));
    NodeLoads weights = zeroLoads(n_ + 1);
    for (std::size_t i = 0; i < n_; ++i) weights.force[i] = pieces_[i].mass * settings_.gravity;
    const std::vector<double> rest = stress_->stresses(weights);
    for (std::size_t i = 0; i < glue_.size(); ++i) glue_[i].restStress = rest[i];
}

// The bond graph's damage model: the same links as the glue (bonds, then ground links), each
// carrying its strength times its area.
void Simulation::buildDamageModel() {
    if (glue_.empty()) return;
    std::vector<DamageLink> links;
    links.reserve(glue_.size());
    const auto add = [&](std::uint32_t a, std::uint32_t b, double area) {
        const std::size_t i = links.size();
        links.push_back({a, b, area, glue_[i].strength * area});
    };
    for (const Bond& b : bonds_) add(b.a, b.b, std::max(b.area, 1e-8));
    for (const GroundLink& g : ground_) add(g.piece, std::uint32_t(n_), g.area);
    damage_ = std::make_unique<DamageModel>(n_ + 1, std::uint32_t(n_), std::move(links),
                                            DamageRules{settings_.damageTransmission, settings_.damageHops,
                                                        settings_.damageHalfLife, settings_.impactTime});
    unsettled_.assign(n_ + 1, false);
}

// The contact impulses of the substep just taken, summed per piece, strike the damage model.
// What the ground, the support or a collider does to a held piece is its ground link's part
// (the model holds it there), so those contacts are left out; asleep pairs have not changed and
// are skipped.
void Simulation::strikeGlue() {
    std::vector<glm::dvec3> blow(n_, glm::dvec3(0.0));
    bool struck = false;
    const auto add = [&](const btCollisionObject* body, int child, const btVector3& impulse, const btCollisionObject* other) {
        const int a = body->getUserIndex();
        if (a < 0) return;
        const std::vector<std::uint32_t>& members = actors_[std::size_t(a)].pieces;
        if (members.size() > 1 && (child < 0 || std::size_t(child) >= members.size())) return;
        const std::uint32_t piece = members.size() == 1 ? members[0] : members[std::size_t(child)];
        if (other->getUserIndex() < 0 && other->isStaticObject() && held(piece)) return;  // its ground link stands for it
        blow[piece] += toGlm(impulse);
        struck = true;
    };
    for (int m = 0; m < w_.dispatcher.getNumManifolds(); ++m) {
        const btPersistentManifold* manifold = w_.dispatcher.getManifoldByIndexInternal(m);
        if (!manifold->getBody0()->isActive() && !manifold->getBody1()->isActive()) continue;  // asleep or fixed: as before
        for (int c = 0; c < manifold->getNumContacts(); ++c) {
            const btManifoldPoint& p = manifold->getContactPoint(c);
            const btVector3 impulse = p.m_normalWorldOnB * p.getAppliedImpulse() +
                                      p.m_lateralFrictionDir1 * p.m_appliedImpulseLateral1 +
                                      p.m_lateralFrictionDir2 * p.m_appliedImpulseLateral2;
            add(manifold->getBody0(), p.m_index0, impulse, manifold->getBody1());
            add(manifold->getBody1(), p.m_index1, -impulse, manifold->getBody0());
        }
    }
    for (std::uint32_t i = 0; struck && i < n_; ++i) damage_->strike(i, glm::length(blow[i]));
}

// The substep's blows damage the bonds near them; those they break go. True when one broke.
// The damage ages every substep, struck or not.
bool Simulation::breakStruckBonds() {
    if (!damage_) return false;
    strikeGlue();
    const std::vector<std::size_t> over = damage_->spread(dt_);
    for (std::size_t link : over) breakLink(link, double(step_ + 1) * dt_);
    return !over.empty();
}

// Adds the weights (in the rest frames) to `loads` and breaks the bonds whose stress exceeds
// their rest stress by more than their strength, the most overloaded first (those over kFront
// of the worst), then solves again without them, for at most `rounds` rounds or until none is
// over: a set of pieces cut loose is balanced by its own inertia and passes its load on no
// further, so a break runs from where the structure is loaded, as a crack does. Only the
// groups with an `active` node are solved, and those a break changed; the ends of the bonds
// broken stay unsettled, for the next substep. True when a bond broke.
bool Simulation::breakBonds(NodeLoads loads, std::vector<bool> active, int rounds) {
    for (std::size_t i = 0; i < n_; ++i)
        loads.force[i] += glm::conjugate(meshOrientation(i)) * (pieces_[i].mass * settings_.gravity);
    bool any = false;
    for (int round = 0; round < rounds; ++round) {
        const std::vector<double> stress = stress_->stresses(loads, &active);
        std::vector<double> over(glue_.size(), 0.0);  // the stress above rest, in strengths
        for (std::size_t i = 0; i < glue_.size(); ++i)
            if (!glue_[i].broken) over[i] = (stress[i] - glue_[i].restStress) / glue_[i].strength;
        const double front = std::max(1.0, kFront * *std::max_element(over.begin(), over.end()));
        bool broke = false;
        for (std::size_t i = 0; i < glue_.size(); ++i) {
            if (over[i] <= front) continue;
            breakLink(i, double(step_ + 1) * dt_);
            const auto [a, b] = linkEnds(i);
            active[a] = active[b] = true;
            broke = true;
        }
        if (!broke) break;
        any = true;
    }
    return any;
}

// One round of the structures that a break changed carrying their weights (Blast's stress
// solver, bounded per step): what lost its support fails after the breach, starting next to it.
bool Simulation::settleSupport() {
    if (!stress_ || std::none_of(unsettled_.begin(), unsettled_.end(), [](bool u) { return u; })) return false;
    std::vector<bool> active = std::exchange(unsettled_, std::vector<bool>(n_ + 1, false));
    return breakBonds(zeroLoads(n_ + 1), std::move(active), 1);
}

double Simulation::totalEnergy() const {
    double e = 0.0;
    for (std::size_t a = 0; a < actors_.size(); ++a)
        if (w_.actors[a]) e += energyOf(*w_.actors[a], actors_[a].info, settings_.gravity);
    if (projectile_) e += energyOf(*projectile_, projectileInfo_, settings_.gravity);
    return e;
}

// A piece's principal frame in the world: its actor's body frame and its place in it.
btTransform Simulation::pieceFrame(std::size_t i) const {
    return w_.actors[actorOf_[i]]->getCenterOfMassTransform() * local_[i];
}

glm::dvec3 Simulation::pieceVelocity(std::size_t i) const {
    const btRigidBody& body = *w_.actors[actorOf_[i]];
    return toGlm(body.getVelocityInLocalPoint(pieceFrame(i).getOrigin() - body.getCenterOfMassPosition()));
}

// A piece's mesh orientation: its principal frame's with the principal frame at rest taken back out.
glm::dquat Simulation::meshOrientation(std::size_t i) const {
    return glm::normalize(toGlm(pieceFrame(i).getRotation()) * toMesh_[i]);
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
    // A library global, always set to the same value here (see sleepWhenSlow).
    gDeactivationTime = btScalar(kSleepAfter);
    gCompoundChildShapePairCallback = childrenCollide;
    gCompoundCompoundChildShapePairCallback = childrenCollide;
    SimulationResult result = Simulation(pieces, bonds, settings, shapes).run(progress);
    addDust(pieces, bonds, settings, result);  // before the chips: it reads the pieces' motion alone
    if (settings.debris.chips) moveChips(pieces, emitChips(pieces, bonds, result, settings), settings, result);
    return result;
}

}  // namespace dawnforge::sim

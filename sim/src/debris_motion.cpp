// Chips moved among the pieces (debris.hpp), with Bullet.
//
// A world of its own: the ground, the support and the colliders as in the pieces' simulation;
// every piece a kinematic hull that follows its recorded motion (interpolated between frames,
// substep by substep); each chip a dynamic body from its release frame, pushed out of its
// crack with its parent's velocity there and its spray. Chips collide with neither of their
// bond's pieces (they start inside them) nor with each other; the pieces never feel them.
// Before its release a chip rides with its parent. Determinism as in rigidbody.cpp: one
// single-threaded world, bodies added in a fixed order, fixed steps, no randomised solver order.
#include "debris.hpp"
#include "hull.hpp"

#include <btBulletDynamicsCommon.h>
#include <glm/gtc/constants.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <set>
#include <utility>

namespace dawnforge::sim {

namespace {

// What a body is (user index 2); its user index is its piece or chip.
enum Kind : int { kGround = 0, kSupportPlane = 1, kCollider = 2, kPiece = 3, kChip = 4 };
constexpr int kChipGroup = 64;  // a broadphase collision filter group Bullet does not use
// A piece that never moves more than this (m, or quaternion component) is static: a standing
// building's pieces shift by float rounding as its actors are remade.
constexpr float kStill = 1e-4f;
// A piece that moves less than this in a frame (m, or quaternion component: 1 mm, 0.1°) sleeps
// through it: rubble creeping at 3 cm/s would keep every chip on it awake to the last frame.
constexpr double kCreep = 1e-3;

// A chip knocked by a piece many times its mass would spin at hundreds of radians a second: none
// spins faster than kChipSpin, four turns a second, which still reads as a tumble.
constexpr double kChipSpin = 25.0;  // rad/s

// One frame's pose of a piece: pivot and mesh orientation.
struct Pose {
    glm::dvec3 x{0.0};
    glm::dquat q{1.0, 0.0, 0.0, 0.0};
};

class ChipDispatcher : public btCollisionDispatcher {
public:
    using btCollisionDispatcher::btCollisionDispatcher;
    std::optional<Support> support;
    const std::vector<ChipSeed>* chips = nullptr;

    bool needsCollision(const btCollisionObject* a, const btCollisionObject* b) override {
        if (a->getUserIndex2() == kChip && b->getUserIndex2() == kChip) return false;
        if (b->getUserIndex2() == kChip) std::swap(a, b);
        if (a->getUserIndex2() == kChip) {
            const ChipSeed& chip = (*chips)[std::size_t(a->getUserIndex())];
            const int kind = b->getUserIndex2();
            if (kind == kPiece && (std::uint32_t(b->getUserIndex()) == chip.parent || std::uint32_t(b->getUserIndex()) == chip.other))
                return false;
            if (support && (kind == kSupportPlane || kind == kCollider) &&
                overSupport(*support, a->getWorldTransform().getOrigin()) != (kind == kSupportPlane))
                return false;  // the support holds it, or the colliders do
        }
        return btCollisionDispatcher::needsCollision(a, b);
    }
};

// Bullet turns a body by at most an eighth of a turn a step, and past that its rotation update
// is wrong (a chip knocked by a piece thousands of times its mass flipped by half a turn every
// step, its turns.bin 1.9 turns a frame while it ended 0.14 from where it began). The spin is
// capped between the solver and the integration, where the solver's impulses have been applied.
class ChipDynamicsWorld : public btDiscreteDynamicsWorld {
public:
    using btDiscreteDynamicsWorld::btDiscreteDynamicsWorld;

protected:
    void integrateTransforms(btScalar timeStep) override {
        for (int i = 0; i < m_nonStaticRigidBodies.size(); ++i) {
            btRigidBody* body = m_nonStaticRigidBodies[i];
            const btScalar spin = body->getAngularVelocity().length();
            if (!body->isStaticOrKinematicObject() && spin > btScalar(kChipSpin))
                body->setAngularVelocity(body->getAngularVelocity() * (btScalar(kChipSpin) / spin));
        }
        btDiscreteDynamicsWorld::integrateTransforms(timeStep);
    }
};

class ChipWorld {
public:
    ChipWorld(std::span<const RigidPiece> pieces, const std::vector<ChipSeed>& chips, const SimulationSettings& settings,
              const SimulationResult& result)
        : pieces_(pieces), chips_(chips), s_(settings), r_(result), n_(pieces.size()),
          dt_(1.0 / settings.fps / settings.substeps), bodies_(chips.size()), path_(chips.size()),
          travelled_(chips.size(), 0.0) {
        dispatcher_.support = settings.support;
        dispatcher_.chips = &chips_;
        world_->setGravity(bt(settings.gravity));
        // Chips touch one piece or the ground at a time, not stacks: a quarter of the pieces' iterations.
        world_->getSolverInfo().m_numIterations = std::max(4, settings.solverIterations / 4);
        world_->getSolverInfo().m_solverMode &= ~SOLVER_RANDMIZE_ORDER;
        world_->getSolverInfo().m_splitImpulse = 1;  // a chip pressed into the ground is not shot out of it
        world_->getSolverInfo().m_splitImpulseTurnErp = 0;  // nor turned by it: only pushed
        addStatic();
        addPieces();
    }
    ~ChipWorld() {
        for (auto& b : owned_) world_->removeRigidBody(b.get());
        world_.reset();
    }

    // frames × chips × 7 and frames × chips, in result's layout.
    std::pair<std::vector<float>, std::vector<float>> run();

private:
    Pose pose(int frame, std::size_t piece) const {
        const float* t = r_.transforms.data() + (std::size_t(frame) * n_ + piece) * 7;
        return {glm::dvec3(t[0], t[1], t[2]), glm::dquat(t[6], t[3], t[4], t[5])};
    }
    Pose chipPose(int frame, std::size_t k) const;
    // A released chip's mesh orientation: its body's with its principal axes taken back out.
    glm::dquat meshOrientation(std::size_t k) const {
        return glm::normalize(toGlm(bodies_[k]->getCenterOfMassTransform().getRotation()) * glm::conjugate(chips_[k].axes));
    }
    btRigidBody& add(std::unique_ptr<btCollisionShape> shape, const btRigidBody::btRigidBodyConstructionInfo& info,
                     Kind kind, int index);
    void addStatic();
    void addPieces();
    void release(std::size_t k, int frame);
    void moveKinematic(int frame, double alpha);
    void record(int frame, float* transforms, float* turns);

    std::span<const RigidPiece> pieces_;
    const std::vector<ChipSeed>& chips_;
    const SimulationSettings& s_;
    const SimulationResult& r_;
    const std::size_t n_;
    const double dt_;
    std::vector<std::unique_ptr<btCollisionShape>> shapes_;
    std::vector<std::unique_ptr<ColliderShape>> colliders_;  // their triangle arrays (the shapes are in shapes_)
    std::vector<std::unique_ptr<btDefaultMotionState>> motions_;
    std::vector<std::unique_ptr<btRigidBody>> owned_;
    std::vector<std::size_t> moving_;      // the pieces that move at some frame: kinematic bodies
    std::vector<btRigidBody*> kinematic_;  // their bodies
    std::vector<btRigidBody*> bodies_;     // per chip, once released
    std::vector<glm::dquat> path_;         // per chip: its orientation followed through the substeps
    std::vector<double> travelled_;        // per chip: radians turned since the last frame
    btDefaultCollisionConfiguration configuration_;
    ChipDispatcher dispatcher_{&configuration_};
    btDbvtBroadphase broadphase_;
    btSequentialImpulseConstraintSolver solver_;
    std::unique_ptr<ChipDynamicsWorld> world_ =
        std::make_unique<ChipDynamicsWorld>(&dispatcher_, &broadphase_, &solver_, &configuration_);
};

btRigidBody& ChipWorld::add(std::unique_ptr<btCollisionShape> shape, const btRigidBody::btRigidBodyConstructionInfo& info,
                            Kind kind, int index) {
    auto body = std::make_unique<btRigidBody>(info);
    body->setUserIndex(index);
    body->setUserIndex2(kind);
    body->setFriction(btScalar(s_.friction));
    body->setRestitution(btScalar(s_.restitution));
    // Chips in a group of their own that does not collide with itself: the broadphase never
    // pairs two chips (a pile of them at one crack would make every pair).
    if (kind == kChip) world_->addRigidBody(body.get(), kChipGroup, btBroadphaseProxy::AllFilter & ~kChipGroup);
    else world_->addRigidBody(body.get());
    shapes_.push_back(std::move(shape));
    owned_.push_back(std::move(body));
    return *owned_.back();
}

void ChipWorld::addStatic() {
    const auto plane = [&](double height, Kind kind) {
        auto shape = std::make_unique<btStaticPlaneShape>(btVector3(0, 1, 0), btScalar(height));
        btRigidBody::btRigidBodyConstructionInfo ci(0, nullptr, shape.get());
        add(std::move(shape), ci, kind, -1);
    };
    if (s_.ground) plane(r_.groundHeight, kGround);
    if (s_.support) plane(s_.support->height, kSupportPlane);
    for (const Mesh& m : s_.colliders) {
        if (m.indices.empty()) continue;  // Bullet's BVH builder crashes on an empty mesh
        std::unique_ptr<ColliderShape>& c = colliders_.emplace_back(colliderShape(m));
        btRigidBody::btRigidBodyConstructionInfo ci(0, nullptr, c->shape.get());
        add(std::move(c->shape), ci, kCollider, -1);
    }
}

// Each piece's hull in its mesh frame (built in parallel, each from its piece alone) at its
// pivot: a kinematic body when the piece moves at some frame, a static one when it never does
// by more than kStill (most of a building that a ball breaches stands: static bodies cost
// nothing a step).
void ChipWorld::addPieces() {
    std::vector<Hull> hulls(n_);
    tbb::parallel_for(std::size_t(0), n_, [&](std::size_t i) {
        hulls[i] = buildHull(pieces_[i], glm::dmat3(1.0), s_.hullVertices, s_.margin);
    });
    const float* t = r_.transforms.data();
    for (std::size_t i = 0; i < n_; ++i) {
        bool moves = false;
        for (int f = 1; f < s_.frames && !moves; ++f) {
            const float* a = t + i * 7;
            const float* b = t + (std::size_t(f) * n_ + i) * 7;
            for (int c = 0; c < 7; ++c) moves = moves || std::abs(a[c] - b[c]) > kStill;
        }
        auto shape = std::make_unique<btConvexHullShape>(&hulls[i].points[0].x(), int(hulls[i].points.size()),
                                                         int(sizeof(btVector3)));
        shape->setMargin(hulls[i].margin);
        const Pose p = pose(0, i);
        motions_.push_back(moves ? std::make_unique<btDefaultMotionState>(btTransform(bt(p.q), bt(p.x))) : nullptr);
        btRigidBody::btRigidBodyConstructionInfo ci(0, motions_.back().get(), shape.get());
        ci.m_startWorldTransform = btTransform(bt(p.q), bt(p.x));
        btRigidBody& body = add(std::move(shape), ci, kPiece, int(i));
        if (!moves) continue;
        body.setCollisionFlags(body.getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
        body.setSleepingThresholds(btScalar(0.1), btScalar(0.2));
        moving_.push_back(i);
        kinematic_.push_back(&body);
    }
}

// Where chip k is at `frame` while it rides with its parent: its rest place carried along.
Pose ChipWorld::chipPose(int frame, std::size_t k) const {
    const ChipSeed& chip = chips_[k];
    const Pose parent = pose(frame, chip.parent);
    return {parent.x + parent.q * (chip.piece.centerOfMass - pieces_[chip.parent].centerOfMass), parent.q};
}

// Chip k leaves its parent at `frame`: a body where it rides, with its parent's velocity there
// (from the last frame's motion) and its spray.
void ChipWorld::release(std::size_t k, int frame) {
    const ChipSeed& chip = chips_[k];
    const Pose now = chipPose(frame, k), before = chipPose(frame - 1, k);
    const Pose parentNow = pose(frame, chip.parent), parentBefore = pose(frame - 1, chip.parent);
    glm::dquat turn = parentNow.q * glm::conjugate(parentBefore.q);
    if (turn.w < 0.0) turn = -turn;
    const double angle = 2.0 * std::acos(std::min(1.0, turn.w));
    const glm::dvec3 axis = glm::length(glm::dvec3(turn.x, turn.y, turn.z)) > 1e-12
                                ? glm::normalize(glm::dvec3(turn.x, turn.y, turn.z)) : glm::dvec3(0.0);
    const glm::dvec3 spin = axis * angle * s_.fps;
    const glm::dvec3 velocity = (now.x - before.x) * s_.fps + chip.spray;

    const glm::dvec3 r = chip.radii;
    const double margin = std::min(0.004, 0.2 * std::min({r.x, r.y, r.z}));
    const std::array<btVector3, 6> points{btVector3(btScalar(r.x - margin), 0, 0), btVector3(btScalar(margin - r.x), 0, 0),
                                          btVector3(0, btScalar(r.y - margin), 0), btVector3(0, btScalar(margin - r.y), 0),
                                          btVector3(0, 0, btScalar(r.z - margin)), btVector3(0, 0, btScalar(margin - r.z))};
    auto shape = std::make_unique<btConvexHullShape>(&points[0].x(), 6, int(sizeof(btVector3)));
    shape->setMargin(btScalar(margin));
    btRigidBody::btRigidBodyConstructionInfo ci(btScalar(chip.piece.mass), nullptr, shape.get(),
                                                bt(octahedronMoments(chip.piece.mass, r)));
    ci.m_startWorldTransform = btTransform(bt(glm::normalize(now.q * chip.axes)), bt(now.x));
    ci.m_linearDamping = btScalar(s_.linearDamping);
    ci.m_angularDamping = btScalar(s_.angularDamping);
    btRigidBody& body = add(std::move(shape), ci, kChip, int(k));
    body.setLinearVelocity(bt(velocity));
    body.setAngularVelocity(bt(glm::length(spin) > kChipSpin ? spin * (kChipSpin / glm::length(spin)) : spin));
    body.setCcdMotionThreshold(btScalar(2.0 * std::min({r.x, r.y, r.z})));  // moving more than its thickness a step
    body.setCcdSweptSphereRadius(btScalar(0.5 * std::min({r.x, r.y, r.z})));
    if (s_.sleep) body.setSleepingThresholds(btScalar(0.1), btScalar(0.2));
    else body.setActivationState(DISABLE_DEACTIVATION);
    bodies_[k] = &body;
    path_[k] = now.q;
    travelled_[k] = 0.0;
}

// The pieces where they are `alpha` of the way from frame - 1 to `frame`. An awake kinematic
// body keeps every chip it touches awake (Bullet's islands), and Bullet never puts one to sleep
// itself: a piece sleeps while it creeps (kCreep) and wakes when it moves again.
void ChipWorld::moveKinematic(int frame, double alpha) {
    for (std::size_t k = 0; k < moving_.size(); ++k) {
        const std::size_t i = moving_[k];
        const Pose a = pose(frame - 1, i), b = pose(frame, i);
        if (glm::length(a.x - b.x) <= kCreep && glm::length(glm::dvec4(a.q.x - b.q.x, a.q.y - b.q.y, a.q.z - b.q.z, a.q.w - b.q.w)) <= kCreep) {
            kinematic_[k]->forceActivationState(ISLAND_SLEEPING);
            continue;
        }
        kinematic_[k]->forceActivationState(ACTIVE_TAG);
        kinematic_[k]->setDeactivationTime(0);
        const glm::dquat q = glm::normalize(glm::slerp(a.q, b.q, alpha));
        motions_[i]->setWorldTransform(btTransform(bt(q), bt(glm::mix(a.x, b.x, alpha))));
    }
}

void ChipWorld::record(int frame, float* transforms, float* turns) {
    for (std::size_t k = 0; k < chips_.size(); ++k) {
        Pose p = chipPose(frame, k);
        double turned = frame > 0 ? double(r_.turns[std::size_t(frame - 1) * n_ + chips_[k].parent]) : 0.0;
        if (bodies_[k]) {
            const btTransform& t = bodies_[k]->getCenterOfMassTransform();
            p = {toGlm(t.getOrigin()), meshOrientation(k)};
            if (p.q.w < 0.0) p.q = -p.q;
            turned = signedTurns(travelled_[k], path_[k], p.q);
            path_[k] = p.q;
            travelled_[k] = 0.0;
        }
        const std::array<double, 7> v{p.x.x, p.x.y, p.x.z, p.q.x, p.q.y, p.q.z, p.q.w};
        for (int c = 0; c < 7; ++c) transforms[k * 7 + std::size_t(c)] = float(v[std::size_t(c)]);
        if (frame > 0) turns[k] = float(turned);
    }
}

std::pair<std::vector<float>, std::vector<float>> ChipWorld::run() {
    const std::size_t c = chips_.size();
    std::vector<float> transforms(std::size_t(s_.frames) * c * 7), turns(std::size_t(s_.frames) * c, 0.0f);
    record(0, transforms.data(), nullptr);
    for (int frame = 1; frame < s_.frames; ++frame) {
        for (std::size_t k = 0; k < c; ++k)
            if (!bodies_[k] && chips_[k].releaseFrame == frame - 1) release(k, frame - 1);
        for (int step = 1; step <= s_.substeps; ++step) {
            moveKinematic(frame, double(step) / s_.substeps);
            world_->stepSimulation(btScalar(dt_), 0, btScalar(dt_));
            for (std::size_t k = 0; k < c; ++k)
                if (bodies_[k]) travelled_[k] += followTurn(path_[k], meshOrientation(k));
        }
        record(frame, transforms.data() + std::size_t(frame) * c * 7, turns.data() + std::size_t(frame - 1) * c);
    }
    return {std::move(transforms), std::move(turns)};
}

// Frame-major arrays of n then c values per frame, each `per` floats.
std::vector<float> interleave(const std::vector<float>& pieces, std::size_t n, const std::vector<float>& chips,
                              std::size_t c, std::size_t frames, std::size_t per) {
    std::vector<float> out;
    out.reserve(frames * (n + c) * per);
    for (std::size_t f = 0; f < frames; ++f) {
        out.insert(out.end(), pieces.begin() + std::ptrdiff_t(f * n * per), pieces.begin() + std::ptrdiff_t((f + 1) * n * per));
        out.insert(out.end(), chips.begin() + std::ptrdiff_t(f * c * per), chips.begin() + std::ptrdiff_t((f + 1) * c * per));
    }
    return out;
}

}  // namespace

void moveChips(std::span<const RigidPiece> pieces, std::vector<ChipSeed> chips, const SimulationSettings& settings,
               SimulationResult& result) {
    if (chips.empty()) return;
    std::pair<std::vector<float>, std::vector<float>> motion;
    {
        ChipWorld world(pieces, chips, settings, result);
        motion = world.run();
    }
    const std::size_t n = pieces.size(), c = chips.size(), frames = std::size_t(result.frames);
    result.transforms = interleave(result.transforms, n, motion.first, c, frames, 7);
    result.turns = interleave(result.turns, n, motion.second, c, frames, 1);
    std::set<std::pair<std::uint32_t, std::uint32_t>> bonds;
    for (ChipSeed& chip : chips) {
        bonds.insert(std::minmax(chip.parent, chip.other));
        result.chips.push_back(std::move(chip.piece));
    }
    result.chipBonds = bonds.size();
    result.pieces = n + c;
}

}  // namespace dawnforge::sim

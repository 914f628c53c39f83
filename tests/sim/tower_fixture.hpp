#pragma once
// A fixture the rigid-body and debris tests share.
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/sim/fracture.hpp>

namespace dawnforge::test {

// A small tower (3 storeys, 6 × 5 m) in 14 glued pieces, standing on y = 0.
inline const sim::FractureResult& smallTower() {
    static const sim::FractureResult result = [] {
        sim::FractureSettings s;
        s.pieces = 14;
        s.seed = 5;
        s.density = 300.0;
        return sim::fractureMesh(makeTower(3, 3.0f, 6.0f, 5.0f), s);
    }();
    return result;
}

}  // namespace dawnforge::test

#pragma once
// Seeds and random numbers. A sub-seed is derived by hashing (seed, purpose, entity id),
// never by drawing from one shared generator in a data-dependent order: that keeps
// output independent of thread count and lets one city tile be generated alone.
#include <cstdint>
#include <string_view>

namespace dawnforge {

// SplitMix64 finaliser: a bijective 64-bit mix.
std::uint64_t mix64(std::uint64_t x);

// lowbias32 (C. Wellons' hash-prospector): a bijective 32-bit mix that GLSL 4.50 reproduces
// exactly (runtime/shaders/interior.glsl), for hashes the CPU and the shaders must share.
constexpr std::uint32_t lowbias32(std::uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

// The seed for one entity and one purpose, e.g. deriveSeed(seed, "lot-split", lotId).
std::uint64_t deriveSeed(std::uint64_t seed, std::string_view purpose, std::uint64_t id = 0);

// A small fast generator (xoshiro256**, seeded through SplitMix64). Same seed, same
// sequence on every platform: no std:: distributions, whose output is unspecified.
class Rng {
public:
    explicit Rng(std::uint64_t seed);
    std::uint64_t next();
    double uniform();                             // [0, 1), 53 random bits
    double uniform(double lo, double hi);         // [lo, hi)
    std::uint64_t below(std::uint64_t bound);     // [0, bound), unbiased; bound > 0
    int range(int lo, int hiInclusive);           // [lo, hi]

private:
    std::uint64_t s_[4];
};

}  // namespace dawnforge

// xoshiro256** by David Blackman and Sebastiano Vigna (https://prng.di.unimi.it/),
// seeded with SplitMix64 as its authors recommend.
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/seed.hpp>

namespace dawnforge {

std::uint64_t mix64(std::uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

std::uint64_t deriveSeed(std::uint64_t seed, std::string_view purpose, std::uint64_t id) {
    // FNV-1a over the purpose, then mixed with the seed and the id in turn.
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (unsigned char c : purpose) h = (h ^ c) * 0x100000001b3ull;
    return mix64(mix64(mix64(seed) ^ h) ^ id);
}

namespace {
std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
}  // namespace

Rng::Rng(std::uint64_t seed) {
    for (std::uint64_t& s : s_) {
        seed += 0x9e3779b97f4a7c15ull;
        s = mix64(seed);
    }
}

std::uint64_t Rng::next() {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
}

double Rng::uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

double Rng::uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

std::uint64_t Rng::below(std::uint64_t bound) {
    DAWNFORGE_ASSERT(bound > 0, "bound must be positive");
    // Lemire's nearly divisionless method, with rejection for exact uniformity.
    __uint128_t m = static_cast<__uint128_t>(next()) * bound;
    auto low = static_cast<std::uint64_t>(m);
    if (low < bound) {
        const std::uint64_t threshold = -bound % bound;
        while (low < threshold) {
            m = static_cast<__uint128_t>(next()) * bound;
            low = static_cast<std::uint64_t>(m);
        }
    }
    return static_cast<std::uint64_t>(m >> 64);
}

int Rng::range(int lo, int hiInclusive) {
    DAWNFORGE_ASSERT(lo <= hiInclusive, "empty range");
    const auto span = static_cast<std::uint64_t>(static_cast<std::int64_t>(hiInclusive) - lo) + 1;
    return static_cast<int>(lo + static_cast<std::int64_t>(below(span)));
}

}  // namespace dawnforge

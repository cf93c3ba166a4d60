#ifndef PARKSLAM_RENDER_SEED_MIX_H_
#define PARKSLAM_RENDER_SEED_MIX_H_

#include <cstdint>

namespace parkslam::render {

// SplitMix64's finaliser: a well-spread 64-bit value from a seed and a tag,
// for the bulk random generators of the renderer (OpenCV's RNG, the per-frame
// noise), where parkslam::Random would be too slow.
inline std::uint64_t MixSeed(std::uint64_t seed, std::uint64_t tag) {
  std::uint64_t z = seed + 0x9e3779b97f4a7c15ull * (tag + 1);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

}  // namespace parkslam::render

#endif  // PARKSLAM_RENDER_SEED_MIX_H_

#ifndef PARKSLAM_COMMON_SEED_MIX_H_
#define PARKSLAM_COMMON_SEED_MIX_H_

#include <cstdint>

namespace parkslam {

// SplitMix64's finaliser: a well-spread 64-bit value from a seed and a tag,
// for the bulk random generators of the renderers (OpenCV's RNG, the per-frame
// noise) and for the seeds of a training set's scenes, where parkslam::Random
// would be too slow or too heavy.
inline std::uint64_t MixSeed(std::uint64_t seed, std::uint64_t tag) {
  std::uint64_t z = seed + 0x9e3779b97f4a7c15ull * (tag + 1);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

}  // namespace parkslam

#endif  // PARKSLAM_COMMON_SEED_MIX_H_

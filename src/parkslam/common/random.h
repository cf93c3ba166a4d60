#ifndef PARKSLAM_COMMON_RANDOM_H_
#define PARKSLAM_COMMON_RANDOM_H_

#include <cstdint>
#include <random>

namespace parkslam {

// A seeded random source. Every stochastic part of the project draws from one
// of these so that a seed reproduces a run bit for bit on the same build.
// std::mt19937_64 is specified by the standard; the distributions below are
// written out here because the standard library's are not portable across
// implementations.
class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}

  // A new independent stream, derived from this one's seed and a tag, so that
  // adding draws to one sensor does not shift the noise of another.
  static Random Derive(std::uint64_t seed, std::uint64_t tag) {
    std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                      static_cast<std::uint32_t>(tag), static_cast<std::uint32_t>(tag >> 32)};
    std::uint64_t derived = 0;
    std::uint32_t words[2];
    seq.generate(words, words + 2);
    derived = (static_cast<std::uint64_t>(words[0]) << 32) | words[1];
    return Random(derived);
  }

  // Uniform in [0, 1).
  double Uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }

  // Uniform integer in [0, n).
  std::uint64_t Index(std::uint64_t n) {
    return static_cast<std::uint64_t>(Uniform() * static_cast<double>(n)) % (n == 0 ? 1 : n);
  }

  bool Bernoulli(double p) { return Uniform() < p; }

  // Standard normal by Box-Muller (both outputs used).
  double Gaussian() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u1 = Uniform();
    while (u1 <= 0.0) u1 = Uniform();
    const double u2 = Uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(2.0 * 3.14159265358979323846 * u2);
    has_spare_ = true;
    return r * std::cos(2.0 * 3.14159265358979323846 * u2);
  }
  double Gaussian(double sigma) { return sigma * Gaussian(); }

  // Poisson by inversion; meant for small means (false detections per frame).
  int Poisson(double mean) {
    const double limit = std::exp(-mean);
    double product = Uniform();
    int k = 0;
    while (product > limit) {
      ++k;
      product *= Uniform();
    }
    return k;
  }

 private:
  std::mt19937_64 engine_;
  bool has_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace parkslam

#endif  // PARKSLAM_COMMON_RANDOM_H_

#pragma once
// Seeded draws that mean the same numbers on every standard library. std::mt19937's output is
// specified bit for bit, but std::uniform_real_distribution, std::normal_distribution and
// std::uniform_int_distribution are not (libstdc++, libc++ and MSVC draw differently from the
// same engine), so a seed printed by a failing test would not reproduce elsewhere. These take
// the engine's raw 32-bit outputs and transform them by formulas written here. Normals go
// through std::log, std::sqrt and std::cos: the same draw everywhere to libm's last bit.
// Draw into named variables (or with draw3), never twice among one call's arguments: their
// order of evaluation is unspecified.
#include <cmath>
#include <cstdint>
#include <random>

#include <Eigen/Core>

namespace grip_test {

/// Uniform in [0, 1) with 53 random bits, from two outputs of a 32-bit engine.
template <class Engine>
double canonical(Engine& g) {
  static_assert(Engine::min() == 0 && Engine::max() == 0xffffffffu, "a 32-bit engine such as std::mt19937");
  const std::uint64_t hi = static_cast<std::uint64_t>(g()) >> 5;             // 27 bits
  const std::uint64_t lo = static_cast<std::uint64_t>(g()) >> 6;             // 26 bits
  return static_cast<double>((hi << 26) | lo) * (1.0 / 9007199254740992.0);  // / 2^53
}

/// Uniform real numbers in [a, b): a drop-in for std::uniform_real_distribution<double>.
class Uniform {
 public:
  Uniform(double a, double b) : a_(a), b_(b) {}
  template <class Engine>
  double operator()(Engine& g) const {
    return a_ + (b_ - a_) * canonical(g);
  }

 private:
  double a_, b_;
};

/// Uniform integers in [lo, hi], exactly (rejection of the engine's top remainder): a drop-in
/// for std::uniform_int_distribution<int>.
class UniformInt {
 public:
  UniformInt(int lo, int hi) : lo_(lo), hi_(hi) {}
  template <class Engine>
  int operator()(Engine& g) const {
    static_assert(Engine::min() == 0 && Engine::max() == 0xffffffffu, "a 32-bit engine such as std::mt19937");
    const std::uint64_t range = static_cast<std::uint64_t>(static_cast<std::int64_t>(hi_) - lo_) + 1;
    const std::uint64_t limit = (std::uint64_t(1) << 32) / range * range;  // accept draws below it
    std::uint64_t v = g();
    while (v >= limit) v = g();
    return static_cast<int>(static_cast<std::int64_t>(lo_) + static_cast<std::int64_t>(v % range));
  }

 private:
  int lo_, hi_;
};

/// Normal numbers (Box-Muller, one of the pair per call, so no hidden state): a drop-in for
/// std::normal_distribution<double>.
class Normal {
 public:
  Normal(double mean, double sd) : mean_(mean), sd_(sd) {}
  template <class Engine>
  double operator()(Engine& g) const {
    const double u = 1.0 - canonical(g);  // (0, 1]: log is finite
    const double v = canonical(g);
    return mean_ + sd_ * std::sqrt(-2.0 * std::log(u)) * std::cos(6.283185307179586 * v);
  }

 private:
  double mean_, sd_;
};

/// Three draws of `draw` in order, as a vector. (Not Vector3d(d(g), d(g), d(g)): function
/// arguments are evaluated in an unspecified order, and g++ and clang take them differently,
/// so the same seed would build different vectors.)
template <class Engine, class Draw>
Eigen::Vector3d draw3(Engine& g, const Draw& draw) {
  const double x = draw(g);
  const double y = draw(g);
  const double z = draw(g);
  return Eigen::Vector3d(x, y, z);
}

}  // namespace grip_test

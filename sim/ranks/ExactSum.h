// An exact sum of floats: every float is an integer multiple of 2^-149, so the sum of any number
// of them (below 2^31) is an integer that fixed-point digits hold without rounding. Addition of
// such sums is integer addition, associative and commutative, so the total is the same whatever
// the order the terms are added in, however they are split between threads or ranks, and is
// rounded only once, at the end (toDouble()). The distributed run (docs/scaling.md) needs that for
// the global sums of a step (the gradient correction, sim/solver/SphPasses.cpp; DFSPH's error means,
// sim/solver/Dfsph.cpp): a serial sum in particle order would depend on which rank holds which
// particles.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "sim/ranks/Communicator.h"

namespace sph::ranks {

class ExactSum {
 public:
  // 32 bits of the fixed-point value per digit, lowest first; digit d weighs 2^(32 d - 149).
  // Floats reach 2^128 (277 bits above 2^-149); the top digit keeps the headroom.
  static constexpr int kDigits = 10;
  using Digits = std::array<std::int64_t, kDigits>;

  // Adds a finite float exactly (non-finite values are the caller's bug).
  void add(float value);
  // Adds v[i] for every i < n with skip[i] == 0 (every i without `skip`), exactly, as add() would
  // one by one, in a third of the time: by exponent first, one integer addition a value; a long
  // array on every thread, to the same digits.
  void addAll(const float* v, std::size_t n, const std::uint8_t* skip = nullptr);
  // Adds another sum (a thread's, a rank's) exactly.
  void merge(const Digits& other);
  const Digits& digits() const { return digits_; }
  Digits& digits() { return digits_; }
  // The sum, rounded to double (the same double for the same exact sum).
  double toDouble() const;
  // Carries into the next digit, so every digit but the top one is below 2^32: then the digits of
  // up to 2^30 sums may be added (what a reduction over ranks does) without overflow.
  void normalise();

 private:
  // Adds value * 2^(shift - 149) (shift >= 0, |value| < 2^62).
  void addShifted(std::int64_t value, int shift);

  Digits digits_{};  // unnormalised: each digit may exceed 32 bits between normalise() calls
  std::uint32_t pending_ = 0;  // additions since the last normalise()
};

// Adds every rank's `sum` and `count` (collective): each rank then holds the totals.
void sumOverRanks(Communicator& ranks, ExactSum& sum, std::int64_t& count);

}  // namespace sph::ranks

// Where DFSPH keeps the fluid pairs of a step (StepScratch::pairs; sim/solver/DfsphPairs.h says
// what a pair holds): rows of grid cells, each filled by one thread, laid end to end in that
// thread's chunks. The memory follows the step's need: a chunk no row used in a pass is given back
// at its end, so a run holds about its largest step's pairs plus a spare chunk a thread, where a
// vector per row kept twice the largest need each row ever had: at the impact of the peer's dam
// break at 1M particles that held 2.5x what MemoryEstimate counted
// (docs/notes/2026-11-26-dfsph-peer-dam-break.md, "Pairs that follow the need").
//
// A pair is one 16-byte record, its index and V gradW, so a pass over the pairs streams one array
// and takes each pair with one load (sim/solver/DfsphPairs.h); its weight (a float the passes
// that need one read: h - r, or the viscosity's own factor) lies in an array of its own.
//
// Every row starts on a cache line of its chunk, so a particle's pairs have the same offset from
// one whatever the thread count or the chunk a row falls in.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <vector>

namespace sph::grid {

// One stored pair: the neighbour's index and V gradW (1/m). Lane 0 of the record read as four
// floats is the index's bits, lanes 1-3 the gradient.
struct alignas(16) PairRecord {
  std::uint32_t index;
  float gx, gy, gz;
};

class PairStore {
 public:
  // Pairs a chunk holds (20 bytes each: 2.6 MB); a row that needs more gets a chunk twice its
  // need, which the thread's later rows then fill.
  static constexpr std::size_t kChunkPairs = std::size_t{1} << 17;

  // One row's pairs: `used` of them from each pointer.
  struct Row {
    PairRecord* pair = nullptr;
    float* weight = nullptr;
    std::size_t used = 0;
  };

  // Before a pass that fills `rows` rows from up to `threads` threads: every row empty.
  void begin(std::size_t rows, int threads) {
    rows_.assign(rows, Placed{});
    if (arenas_.size() < static_cast<std::size_t>(threads)) arenas_.resize(threads);
    for (Arena& a : arenas_) a.current = 0, a.fill = 0;
  }

  // Room for `n` more pairs at the end of `row`, which thread `thread` fills alone; returns the
  // row with its pointers moved to its end (the caller writes there, then calls add()).
  Row room(std::size_t row, int thread, std::size_t n) {
    Placed& p = rows_[row];
    Arena& a = arenas_[thread];
    if (!p.chunk) {  // the row's first cell: start it on the next cache line of the arena
      if (a.chunks.empty()) a.chunks.push_back(std::make_unique<Chunk>(kChunkPairs));
      p.chunk = a.chunks[a.current].get();
      p.start = (a.fill + kLine - 1) / kLine * kLine;
    }
    if (p.start + p.used + n > p.chunk->capacity) moveRow(a, p, p.used + n);
    const std::size_t at = p.start + p.used;
    Chunk& c = *p.chunk;
    return {c.pair.get() + at, c.weight.get() + at, 0};
  }
  // The row holds `count` more pairs (written at what room() returned).
  void add(std::size_t row, int thread, std::size_t count) {
    Placed& p = rows_[row];
    p.used += count;
    arenas_[thread].fill = p.start + p.used;
  }
  // After the pass: each thread's chunks past the one it filled last are given back but one.
  void end() {
    for (Arena& a : arenas_) {
      const std::size_t keep = a.chunks.empty() ? 0 : a.current + 2;
      if (a.chunks.size() > keep) a.chunks.resize(keep);
    }
  }

  Row row(std::size_t r) const {
    const Placed& p = rows_[r];
    if (!p.chunk) return {};
    const Chunk& c = *p.chunk;
    return {c.pair.get() + p.start, c.weight.get() + p.start, p.used};
  }
  // Pairs stored by the last pass, and the bytes the store holds now.
  std::size_t pairs() const {
    std::size_t n = 0;
    for (const Placed& p : rows_) n += p.used;
    return n;
  }
  std::size_t bytesHeld() const {
    std::size_t n = 0;
    for (const Arena& a : arenas_) {
      for (const auto& c : a.chunks) n += c->capacity * kBytesPerPair;
    }
    return n;
  }
  static constexpr std::size_t kBytesPerPair = sizeof(PairRecord) + sizeof(float);

 private:
  // Rows start on a multiple of this many pairs: a cache line of h - r, four of records.
  static constexpr std::size_t kLine = 64 / sizeof(float);

  struct FreeDelete {
    void operator()(void* p) const { std::free(p); }
  };
  template <class T>
  static std::unique_ptr<T[], FreeDelete> lineAligned(std::size_t n) {
    void* p = std::aligned_alloc(64, (n * sizeof(T) + 63) / 64 * 64);
    if (!p) throw std::bad_alloc();
    return std::unique_ptr<T[], FreeDelete>(static_cast<T*>(p));
  }
  struct Chunk {
    explicit Chunk(std::size_t n)
        : capacity(n), pair(lineAligned<PairRecord>(n)), weight(lineAligned<float>(n)) {}
    std::size_t capacity;
    std::unique_ptr<PairRecord[], FreeDelete> pair;
    std::unique_ptr<float[], FreeDelete> weight;
  };
  // One thread's chunks; it fills chunks[current] up to fill. On a cache line of its own: every
  // particle's pairs move `fill`, and neighbouring threads' arenas would share a line.
  struct alignas(64) Arena {
    std::vector<std::unique_ptr<Chunk>> chunks;
    std::size_t current = 0, fill = 0;
  };
  struct Placed {  // a row: `used` pairs from `start` in `chunk`
    Chunk* chunk = nullptr;
    std::size_t start = 0, used = 0;
  };

  // The row does not fit where it is: on to the thread's next chunk (a new one if it has none
  // free or it is too small: then one of twice the need), its pairs so far copied along. The row
  // is the last thing in its chunk, so nothing else moves.
  void moveRow(Arena& a, Placed& p, std::size_t need) {
    ++a.current;
    if (a.current < a.chunks.size() && a.chunks[a.current]->capacity < need) {
      a.chunks.erase(a.chunks.begin() + static_cast<std::ptrdiff_t>(a.current), a.chunks.end());
    }
    if (a.current == a.chunks.size())
      a.chunks.push_back(std::make_unique<Chunk>(std::max(kChunkPairs, 2 * need)));
    Chunk& to = *a.chunks[a.current];
    const Chunk& from = *p.chunk;
    const std::size_t s = p.start, u = p.used;
    std::memcpy(to.pair.get(), from.pair.get() + s, u * sizeof(PairRecord));
    std::memcpy(to.weight.get(), from.weight.get() + s, u * sizeof(float));
    p.chunk = &to, p.start = 0;
  }

  std::vector<Placed> rows_;
  std::vector<Arena> arenas_;
};

}  // namespace sph::grid

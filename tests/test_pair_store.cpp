// DFSPH's pair store (sim/grid/PairStore.h): rows keep what was written to them, start on a cache line
// wherever they land, and the memory held follows the last pass's need instead of the most any
// row ever needed (which reached 2.5x MemoryEstimate at the impact of a 1M-particle dam break).
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "sim/grid/PairStore.h"

namespace sph {
namespace {

constexpr std::size_t kChunk = grid::PairStore::kChunkPairs;

// Appends `n` pairs to `row` from `thread` in pieces of `piece` (as the factor pass does a cell at
// a time, asking for room for more than it keeps), pair q of the row holding q + 1000 row.
void fill(grid::PairStore& s, std::size_t row, int thread, std::size_t n, std::size_t piece) {
  for (std::size_t done = 0; done < n;) {
    const std::size_t take = std::min(piece, n - done);
    const grid::PairStore::Row to = s.room(row, thread, take + 16);
    for (std::size_t q = 0; q < take; ++q) {
      const auto v = static_cast<std::uint32_t>(done + q + 1000 * row);
      to.pair[q] = {v, static_cast<float>(v), -static_cast<float>(v), 0.5f * static_cast<float>(v)};
      to.weight[q] = 2.0f * static_cast<float>(v);
    }
    s.add(row, thread, take);
    done += take;
  }
}

void expectRow(const grid::PairStore& s, std::size_t row, std::size_t n) {
  const grid::PairStore::Row r = s.row(row);
  ASSERT_EQ(r.used, n) << "row " << row;
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(r.pair) % 64, 0u) << "row " << row;
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(r.weight) % 64, 0u) << "row " << row;
  for (std::size_t q = 0; q < n; ++q) {
    const auto v = static_cast<std::uint32_t>(q + 1000 * row);
    const grid::PairRecord& p = r.pair[q];
    if (p.index != v || p.gx != static_cast<float>(v) || p.gy != -static_cast<float>(v) ||
        p.gz != 0.5f * static_cast<float>(v) || r.weight[q] != 2.0f * static_cast<float>(v)) {
      ADD_FAILURE() << "row " << row << " pair " << q << " changed";
      return;
    }
  }
}

TEST(PairStore, RowsKeepTheirPairsAcrossChunksAndStartOnACacheLine) {
  grid::PairStore s;
  s.begin(5, 2);
  // Rows of odd lengths from two threads, one larger than a chunk (a chunk of its own), and
  // enough in all that rows move to a thread's next chunk with their first cells copied along.
  const std::size_t sizes[5] = {kChunk / 3 + 5, kChunk / 2 + 7, 2 * kChunk + 3, 13, kChunk / 2};
  for (std::size_t row = 0; row < 5; ++row) fill(s, row, static_cast<int>(row % 2), sizes[row], 97);
  s.end();
  for (std::size_t row = 0; row < 5; ++row) expectRow(s, row, sizes[row]);
  std::size_t total = 0;
  for (std::size_t n : sizes) total += n;
  EXPECT_EQ(s.pairs(), total);
}

TEST(PairStore, HoldsWhatTheLastPassNeededNotTheMostEver) {
  grid::PairStore s;
  // A pass as at an impact: ten chunks of pairs over 200 rows of one thread (a row is 5% of a
  // chunk, about the longest at 117k particles)...
  constexpr std::size_t kRow = kChunk / 20;
  s.begin(200, 1);
  for (std::size_t row = 0; row < 200; ++row) fill(s, row, 0, kRow, 200);
  s.end();
  const std::size_t chunk = kChunk * grid::PairStore::kBytesPerPair;
  EXPECT_GE(s.bytesHeld(), 10 * chunk);
  EXPECT_LE(s.bytesHeld(), 13 * chunk) << "a chunk's unused end and a spare";
  // ...then the fluid in other rows and a fiftieth as many pairs: the store gives back all but
  // the chunk this pass filled and a spare.
  s.begin(200, 1);
  for (std::size_t row = 30; row < 34; ++row) fill(s, row, 0, kRow, 200);
  s.end();
  for (std::size_t row = 30; row < 34; ++row) expectRow(s, row, kRow);
  EXPECT_EQ(s.row(0).used, 0u);
  EXPECT_LE(s.bytesHeld(), 2 * chunk);
}

}  // namespace
}  // namespace sph

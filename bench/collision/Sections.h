// bench_collision (docs/benchmarks.md, "CDT collision pass"): the options and the four sections
// it prints, one file each: Table.cpp (the thesis's Table 4-1 layout), Recall.cpp (recall of
// each method against exact), FailureModes.cpp (the paper's four failure modes) and
// Improvements.cpp (our improvements, before and after). main.cpp parses the command line.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace sph::collisionbench {

struct Options {
  std::vector<std::size_t> sizes = {50000, 100000, 150000, 200000};
  int steps = 5;
  double warm = 0.35;
  std::size_t recallSize = 100000;
  std::string csv;  // improvements: also write the rows here (recall vs ms, for plot_sweep.py)
};

void printTable(const Options& o);
void printRecall(const Options& o);
void printModes(const Options& o);
void printImprovements(const Options& o);

}  // namespace sph::collisionbench

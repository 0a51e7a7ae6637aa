// What `sphsplat bench` leaves behind (docs/benchmarks.md): a CSV with one row per variant, a
// markdown table ready to paste into the docs (with the command, machine and date), and a PNG of
// wall time against error with the Pareto front marked, drawn by scripts/plot_sweep.py.
#pragma once

#include <string>
#include <vector>

#include "bench/sweep/SweepRunner.h"

namespace sph::sweep {

// Where and how the report was made, for the markdown header.
struct ReportContext {
  std::string command;  // the command line that reproduces it
  std::string machine;  // "2 cores, Intel(R) Xeon(R) Processor"
  std::string date;     // "2026-11-22 01:19 UTC"
};

ReportContext currentReportContext(const std::string& command);

// Value of a named column of one row ("wall_s", "ms_per_step", a metric column); NaN if none.
double columnValue(const SweepResult& result, const VariantResult& row, const std::string& column);

// Rows on the Pareto front of (x, y), both minimised, among the stable rows with both values.
std::vector<bool> paretoFront(const SweepResult& result, const std::string& x,
                              const std::string& y);

// The plotted error column: the sweep's plot.y, else the first metric column; "" without a plot
// section or metric.
std::string plotErrorColumn(const SweepResult& result);

void writeCsv(const SweepResult& result, const std::string& path);
void writeMarkdown(const SweepResult& result, const ReportContext& context, const std::string& path,
                   const std::string& pngName);

// Runs the plot script; returns "" on success, else what went wrong (one line).
std::string runPlot(const SweepResult& result, const std::string& python, const std::string& script,
                    const std::string& csvPath, const std::string& pngPath);

}  // namespace sph::sweep

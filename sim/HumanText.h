// Numbers as people read them in progress lines, summaries and messages: "2.30M", "41.3 ms",
// "3m14s". One home, so every command writes them alike.
#pragma once

#include <string>

namespace sph {

// 950, 12.5k, 2.30M: counts and rates.
std::string humanCount(double v);
// 12.0 us, 41.3 ms, 7.2 s, 3m14s.
std::string humanSeconds(double s);
// 512 bytes, 41.3 MB, 15.3 GB, 2.1e+04 TB (decimal units).
std::string humanBytes(double bytes);

}  // namespace sph

// Bob Jenkins' lookup3 hash ("hashlittle", 2006, public domain), which HDF5 uses as the checksum
// of its version 2 metadata (the HDF5 file format specification: "Appendix C: Jenkins' lookup3
// Hash Function for Checksums"), with seed 0. The cache fuzzer recomputes it after changing a
// field of a checksummed block, so that HDF5 accepts the block and meets the changed field.
#pragma once

#include <cstddef>
#include <cstdint>

namespace sph::fuzz {

std::uint32_t lookup3(const std::uint8_t* data, std::size_t length, std::uint32_t seed = 0);

}  // namespace sph::fuzz

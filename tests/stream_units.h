// A stream as a list of units, for tests that take streams apart and put them together again
// (crafted and corrupted streams): split() gives the units, join() writes them back with
// correct CRCs.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "bitstream/units.h"

namespace tdvo {
namespace test {

struct Unit {
  uint8_t type;
  std::vector<uint8_t> payload;
};

inline std::vector<Unit> split(const std::vector<uint8_t>& stream) {
  UnitReader reader(stream.data(), stream.size(), "split");
  std::vector<Unit> units;
  UnitView u;
  while (reader.next(u))
    units.push_back({u.type, std::vector<uint8_t>(u.payload, u.payload + u.size)});
  return units;
}

// Joins units into a stream with correct CRCs.
inline std::vector<uint8_t> join(const std::vector<Unit>& units) {
  UnitWriter writer;
  for (const Unit& u : units)
    writer.write(static_cast<UnitType>(u.type), u.payload);
  return writer.bytes();
}

// How many units of `type` a stream has.
inline size_t countUnits(const std::vector<uint8_t>& stream, UnitType type) {
  UnitReader reader(stream.data(), stream.size(), "count");
  UnitView unit;
  size_t count = 0;
  while (reader.next(unit))
    count += unit.type == static_cast<uint8_t>(type);
  return count;
}

}  // namespace test
}  // namespace tdvo

// Fuzz target: the unit container (UnitReader: magic, unit_type, unit_size, CRC) and the
// byte-coded syntax structures (syntax.h) of each unit, without any decoding behind them.
//
// The input is a .3dvo stream. It is walked twice: as it is (so size, truncation and CRC checks
// are exercised), then with repaired CRCs (fuzz_support.h), parsing every unit's payload with
// the structure its unit_type names. Seeds: the conformance streams (those with ATTRIBUTES
// units among them; the stream target decodes their payloads).
#include <cstdint>

#include "bitstream/syntax.h"
#include "bitstream/units.h"
#include "common/core/error.h"
#include "fuzz/fuzz_support.h"

namespace {

template <class T>
void parse(const tdvo::UnitView& unit) {
  tdvo::ByteReader reader(unit.payload, unit.size, unit.describe(), unit.payloadOffset);
  T value;
  transfer(reader, value);
  reader.expectEnd("the structure");
}

void walk(const uint8_t* data, size_t size) {
  try {
    tdvo::UnitReader reader(data, size, "fuzz.3dvo");
    tdvo::UnitView unit;
    while (reader.next(unit)) {
      try {
        switch (static_cast<tdvo::UnitType>(unit.type)) {
          case tdvo::UnitType::kSequenceHeader:
            parse<tdvo::SequenceHeader>(unit);
            break;
          case tdvo::UnitType::kGomHeader:
            parse<tdvo::GomHeader>(unit);
            break;
          case tdvo::UnitType::kIMesh:
            parse<tdvo::IMeshUnit>(unit);
            break;
          case tdvo::UnitType::kPMesh:
            parse<tdvo::PMeshUnit>(unit);
            break;
          case tdvo::UnitType::kVertexOrder:
            parse<tdvo::VertexOrderUnit>(unit);
            break;
          case tdvo::UnitType::kAttributes: {
            // The value counts' bound comes from the I mesh: here the largest one can have.
            tdvo::ByteReader reader(unit.payload, unit.size, unit.describe(), unit.payloadOffset);
            tdvo::AttributesUnit at;
            at.maxValues = 3 * tdvo::kMaxTriangles;
            transfer(reader, at);
            reader.expectEnd("the structure");
            break;
          }
          default:  // unknown to the container: the decoder rejects it by type
            break;
        }
      } catch (const tdvo::Error&) {
        // A bad payload; the container walk goes on with the next unit.
      }
    }
  } catch (const tdvo::Error&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  walk(data, size);
  const std::vector<uint8_t> repaired = tdvo::fuzz::withValidCrcs(data, size);
  walk(repaired.data(), repaired.size());
  return 0;
}

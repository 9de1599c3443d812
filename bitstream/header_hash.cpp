#include "bitstream/header_hash.h"

#include "bitstream/byte_io.h"
#include "bitstream/units.h"
#include "common/core/error.h"
#include "common/core/md5.h"

namespace tdvo {

std::string sequenceHeaderHashLine(const SequenceHeader& sh) {
  const std::vector<uint8_t> payload = serialise(sh);
  Md5 md5;
  md5.update(payload.data(), payload.size());
  return "MD5 header=" + toHex(md5.finish());
}

std::string sequenceHeaderHashLine(const std::vector<uint8_t>& stream, const std::string& name) {
  UnitReader reader(stream.data(), stream.size(), name);
  UnitView unit;
  check(reader.next(unit) && unit.type == static_cast<uint8_t>(UnitType::kSequenceHeader),
        name + ": the stream does not start with a SEQUENCE_HEADER unit");
  ByteReader bytes(unit.payload, unit.size, name, unit.payloadOffset);
  SequenceHeader sh;
  transfer(bytes, sh);
  return sequenceHeaderHashLine(sh);
}

}  // namespace tdvo

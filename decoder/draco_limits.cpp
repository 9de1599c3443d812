#include "decoder/draco_limits.h"

#include <draco/compression/config/decoder_options.h>
#include <draco/compression/mesh/mesh_edgebreaker_decoder.h>
#include <draco/compression/mesh/mesh_sequential_decoder.h>
#include <draco/mesh/mesh.h>

#include <cstring>

#include "bitstream/syntax.h"
#include "common/core/error.h"

namespace tdvo {

namespace {

// Constants of the Draco bitstream specification.
constexpr char kDracoMagic[5] = {'D', 'R', 'A', 'C', 'O'};
constexpr uint8_t kTriangularMesh = 1;
constexpr uint8_t kSequentialEncoding = 0, kEdgebreakerEncoding = 1;
constexpr uint16_t kMetadataFlag = 0x8000;
constexpr uint8_t kMaxTraversalType = 2;

class HeaderReader {
 public:
  HeaderReader(const std::vector<uint8_t>& data, const std::string& context)
      : data_(data), context_(context) {}

  uint8_t u8(const char* name) {
    need(1, name);
    return data_[pos_++];
  }
  uint16_t u16(const char* name) {
    need(2, name);
    const uint16_t v = static_cast<uint16_t>(data_[pos_] | data_[pos_ + 1] << 8);
    pos_ += 2;
    return v;
  }
  // varUI32: little-endian base-128, at most 5 bytes, the value must fit 32 bits.
  uint32_t varint(const char* name) {
    uint64_t v = 0;
    for (int shift = 0; shift < 35; shift += 7) {
      const uint8_t b = u8(name);
      v |= uint64_t{b & 0x7Fu} << shift;
      if (!(b & 0x80)) {
        if (v > UINT32_MAX) fail(std::string(name) + " does not fit 32 bits");
        return static_cast<uint32_t>(v);
      }
    }
    fail(std::string(name) + " is longer than 5 bytes");
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(context_ + ": im_draco_payload: " + what);
  }

 private:
  void need(size_t n, const char* name) const {
    if (data_.size() - pos_ < n) fail(std::string("ends inside the Draco header (") + name + ")");
  }
  const std::vector<uint8_t>& data_;
  const std::string& context_;
  size_t pos_ = 0;
};

}  // namespace

DracoMeshCounts checkDracoMeshCounts(const std::vector<uint8_t>& payload,
                                     const std::string& context) {
  HeaderReader in(payload, context);
  if (payload.size() < sizeof kDracoMagic ||
      std::memcmp(payload.data(), kDracoMagic, sizeof kDracoMagic) != 0)
    in.fail("not a Draco bitstream (no \"DRACO\" at its start)");
  for (size_t i = 0; i < sizeof kDracoMagic; ++i)
    in.u8("draco_string");
  DracoMeshCounts c;
  c.versionMajor = in.u8("major_version");
  c.versionMinor = in.u8("minor_version");
  if (in.u8("encoder_type") != kTriangularMesh) in.fail("not a Draco triangle mesh");
  if (c.versionMajor != 2 || c.versionMinor != 2)
    in.fail("Draco bitstream version " + std::to_string(c.versionMajor) + "." +
            std::to_string(c.versionMinor) + " (3DVO takes 2.2, written by Draco 1.5)");
  c.encoderMethod = in.u8("encoder_method");
  const uint16_t flags = in.u16("flags");
  if (flags & kMetadataFlag) in.fail("carries Draco metadata (not allowed in 3DVO)");

  if (c.encoderMethod == kSequentialEncoding) {
    c.numFaces = in.varint("num_faces");
    c.numVertices = in.varint("num_points");
  } else if (c.encoderMethod == kEdgebreakerEncoding) {
    c.traversalType = in.u8("edgebreaker_traversal_type");
    if (c.traversalType > kMaxTraversalType)
      in.fail("unknown Edgebreaker traversal type " + std::to_string(c.traversalType));
    c.numVertices = in.varint("num_encoded_vertices");
    c.numFaces = in.varint("num_faces");
    in.u8("num_attribute_data");
    const uint32_t numSymbols = in.varint("num_encoded_symbols");
    c.numSplitSymbols = in.varint("num_encoded_split_symbols");
    if (numSymbols > c.numFaces || c.numSplitSymbols > numSymbols)
      in.fail("inconsistent Edgebreaker counts (" + std::to_string(c.numFaces) + " faces, " +
              std::to_string(numSymbols) + " symbols, " + std::to_string(c.numSplitSymbols) +
              " split symbols)");
  } else {
    in.fail("unknown Draco encoding method " + std::to_string(c.encoderMethod));
  }
  if (c.numVertices > kMaxVertices)
    in.fail("declares " + std::to_string(c.numVertices) + " vertices (limit " +
            std::to_string(kMaxVertices) + ")");
  if (c.numFaces > kMaxTriangles)
    in.fail("declares " + std::to_string(c.numFaces) + " triangles (limit " +
            std::to_string(kMaxTriangles) + ")");
  return c;
}

void checkDracoMemory(const DracoMeshCounts& counts, uint64_t bytesRead, uint64_t perByte,
                      const std::string& context) {
  if (perByte == 0) return;
  // counts < 2^32: no overflow. need <= free + perByte x bytesRead, without the product.
  const uint64_t need =
      kMeshBytesPerVertex * counts.numVertices + kMeshBytesPerFace * counts.numFaces;
  if (need <= kMeshMemoryFree || (need - kMeshMemoryFree - 1) / perByte < bytesRead) return;
  throw Error(context + ": im_draco_payload: " + std::to_string(counts.numVertices) +
              " vertices and " + std::to_string(counts.numFaces) + " faces need about " +
              std::to_string(need >> 20) + " MiB to decode, more than " +
              std::to_string(bytesRead) + " stream bytes allow (" +
              std::to_string(kMeshMemoryFree >> 20) + " MiB + " + std::to_string(perByte) +
              " bytes per stream byte; MaxMeshMemoryPerByte)");
}

namespace {

// Draco's attribute and data type codes (draco/attributes/geometry_attribute.h,
// draco/core/draco_types.h).
constexpr uint8_t kDracoPosition = 0;
constexpr uint8_t kDracoInt32 = 5;

// A Draco mesh decoder that checks the attribute descriptors before its base class reads them.
template <class Base>
class CheckedDecoder : public Base {
 public:
  explicit CheckedDecoder(bool edgebreaker) : edgebreaker_(edgebreaker) {}
  const std::string& refusal() const { return refusal_; }

 protected:
  bool DecodePointAttributes() override {
    draco::DecoderBuffer* buffer = this->buffer();
    refusal_ =
        checkDracoAttributeDescriptors(reinterpret_cast<const uint8_t*>(buffer->data_head()),
                                       static_cast<size_t>(buffer->remaining_size()), edgebreaker_);
    if (!refusal_.empty()) return false;
    return Base::DecodePointAttributes();
  }

 private:
  bool edgebreaker_;
  std::string refusal_;
};

template <class Base>
std::unique_ptr<draco::Mesh> decodeWith(const std::vector<uint8_t>& payload, bool edgebreaker,
                                        const std::string& context) {
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(payload.data()), payload.size());
  auto mesh = std::make_unique<draco::Mesh>();
  CheckedDecoder<Base> decoder(edgebreaker);
  const draco::Status status = decoder.Decode(draco::DecoderOptions(), &buffer, mesh.get());
  if (!decoder.refusal().empty()) throw Error(context + ": im_draco_payload: " + decoder.refusal());
  if (!status.ok())
    throw Error(context + ": Draco cannot decode im_draco_payload: " + status.error_msg_string());
  return mesh;
}

}  // namespace

std::string checkDracoAttributeDescriptors(const uint8_t* data, size_t size, bool edgebreaker) {
  size_t pos = 0;
  bool ended = false;
  auto u8 = [&]() -> uint8_t {
    if (pos >= size) {
      ended = true;
      return 0;
    }
    return data[pos++];
  };
  auto varint = [&]() -> uint64_t {
    uint64_t v = 0;
    for (int shift = 0; shift < 35; shift += 7) {
      const uint8_t b = u8();
      v |= uint64_t{b & 0x7Fu} << shift;
      if (!(b & 0x80)) return v;
    }
    return UINT64_MAX;
  };
  const std::string where = "Draco attribute data: ";
  const uint8_t decoders = u8();
  if (ended) return where + "ends before num_attributes_decoders";
  if (decoders != 1)
    return where + std::to_string(decoders) + " attribute decoders (an I mesh has 1)";
  if (edgebreaker) {
    u8();  // att_data_id
    u8();  // decoder_type
    u8();  // traversal_method
  }
  const uint64_t attributes = varint();
  if (ended) return where + "ends inside the attribute decoder's header";
  if (attributes != 1)
    return where +
           (attributes == UINT64_MAX ? std::string("a num_attributes beyond 32 bits")
                                     : std::to_string(attributes) + " attributes") +
           " (an I mesh has 1: POSITION)";
  const uint8_t type = u8(), dataType = u8(), components = u8();
  if (ended) return where + "ends inside the attribute descriptor";
  if (type != kDracoPosition || dataType != kDracoInt32 || components != 3)
    return where + "attribute of type " + std::to_string(type) + ", data type " +
           std::to_string(dataType) + ", " + std::to_string(components) +
           " components (an I mesh has one POSITION attribute of 3 int32 components)";
  return "";
}

std::unique_ptr<draco::Mesh> decodeCheckedDracoMesh(const std::vector<uint8_t>& payload,
                                                    const DracoMeshCounts& counts,
                                                    const std::string& context) {
  if (counts.encoderMethod == kEdgebreakerEncoding)
    return decodeWith<draco::MeshEdgebreakerDecoder>(payload, true, context);
  return decodeWith<draco::MeshSequentialDecoder>(payload, false, context);
}

}  // namespace tdvo

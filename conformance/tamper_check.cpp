// Conformance tamper check: flips one byte of a conformance stream and checks that
// `3dvo-dec --verify` rejects the result with exit code 1 and one "3dvo-dec: error:" line
// (a crash or an accepted stream fails the test).
//
//   tamper_check DECODER STREAM MD5LOG WHERE WORKFILE      WHERE: second-unit | middle | last
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 6) {
    std::fprintf(stderr, "usage: tamper_check DECODER STREAM MD5LOG WHERE WORKFILE\n");
    return 2;
  }
  const std::string decoder = argv[1], stream = argv[2], md5 = argv[3], where = argv[4],
                    work = argv[5];
  std::ifstream in(stream, std::ios::binary);
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                   std::istreambuf_iterator<char>());
  if (bytes.size() < 20) {
    std::fprintf(stderr, "%s: too short for a conformance stream\n", stream.c_str());
    return 2;
  }
  size_t offset = bytes.size() - 1;
  if (where == "middle") {
    offset = bytes.size() / 2;
  } else if (where == "second-unit") {
    // "3DVO", then unit 0: type, size (u32 LE), payload, CRC; then unit 1's type and size.
    const size_t size0 = bytes[5] | bytes[6] << 8 | bytes[7] << 16 | size_t(bytes[8]) << 24;
    offset = 4 + 9 + size0 + 5;
  } else if (where != "last") {
    std::fprintf(stderr, "unknown position '%s'\n", where.c_str());
    return 2;
  }
  if (offset >= bytes.size()) return 2;
  bytes[offset] ^= 0x5A;
  std::ofstream(work, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  const std::string errors = work + ".stderr";
  const std::string command =
      "'" + decoder + "' -i '" + work + "' --verify '" + md5 + "' > /dev/null 2> '" + errors + "'";
  const int status = std::system(command.c_str());
  std::ifstream errorStream(errors);
  const std::string message((std::istreambuf_iterator<char>(errorStream)),
                            std::istreambuf_iterator<char>());
  std::remove(work.c_str());
  std::remove(errors.c_str());
  const bool exitedOne = status != -1 && WIFEXITED(status) && WEXITSTATUS(status) == 1;
  if (!exitedOne || message.rfind("3dvo-dec: error: ", 0) != 0) {
    std::fprintf(stderr,
                 "byte %zu flipped: expected exit code 1 and an error line, got status %d: %s\n",
                 offset, status, message.c_str());
    return 1;
  }
  std::printf("byte %zu flipped -> rejected: %s", offset, message.c_str());
  return 0;
}

// Fuzz target: the cfg parser (OptionTable) with the encoder's real option table
// (EncoderParams), its semantic checks (validate) and the frame patterns it accepts.
//
// The input is cfg text. It is applied twice to fresh tables: as a cfg file (parseText), and
// line by line as command-line arguments (parseCommandLine; "-c", which would open a file the
// input names, and "--help", which prints, are left out). Whatever a table accepts is printed
// back (effectiveConfig), which must read back to the same table, and its frame patterns are
// expanded. Seeds: cfg/ and conformance/cfg/ and fuzz/seeds/cfg/.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "common/core/config.h"
#include "common/core/error.h"
#include "common/core/sequence.h"
#include "encoder/encoder_params.h"
#include "fuzz/fuzz_support.h"

namespace {

// The printed configuration reads back to the same table: a fresh table given it prints it
// again, unchanged (the keys derived while unset stay unset), unless a value no cfg line can
// hold had to be printed as a comment.
void readsBack(const std::string& effective) {
  if (effective.find("(a cfg line cannot hold") != std::string::npos) return;
  std::string again;
  try {
    tdvo::EncoderParams params;
    tdvo::OptionTable table("3dvo-enc", "fuzz");
    params.registerOptions(table);
    table.parseText(effective, "effective");
    again = table.effectiveConfig();
  } catch (const tdvo::Error& e) {
    again = std::string("error: ") + e.what();
  }
  if (again != effective) {
    std::fprintf(stderr,
                 "cfg fuzz target: the effective configuration does not read back:\n"
                 "%s\n--- read back ---\n%s\n",
                 effective.c_str(), again.c_str());
    std::abort();
  }
}

void accepted(const tdvo::OptionTable& table, const tdvo::EncoderParams& params) {
  readsBack(table.effectiveConfig());
  params.validate();
  tdvo::framePath(params.inputMeshPattern, params.firstFrame);
  tdvo::framePath(params.inputMeshPattern, params.firstFrame + params.frameCount - 1);
  if (!params.reconMeshPattern.empty()) tdvo::framePath(params.reconMeshPattern, 0);
  params.effectiveLambda();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    tdvo::EncoderParams params;
    tdvo::OptionTable table("3dvo-enc", "fuzz");
    params.registerOptions(table);
    table.parseText(text, "fuzz.cfg");
    accepted(table, params);
  } catch (const tdvo::Error&) {
  }
  try {
    std::vector<std::string> args = {"3dvo-enc"};
    size_t start = 0;
    while (start <= text.size()) {
      size_t end = text.find('\n', start);
      if (end == std::string::npos) end = text.size();
      const std::string arg = text.substr(start, end - start);
      if (arg != "-c" && arg != "-h" && arg != "--help") args.push_back(arg);
      start = end + 1;
    }
    std::vector<const char*> argv;
    for (const std::string& a : args)
      argv.push_back(a.c_str());
    tdvo::EncoderParams params;
    tdvo::OptionTable table("3dvo-enc", "fuzz");
    params.registerOptions(table);
    table.parseCommandLine(static_cast<int>(argv.size()), argv.data());
    accepted(table, params);
  } catch (const tdvo::Error&) {
  }
  return 0;
}

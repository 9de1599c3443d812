// Fuzz target: the dataset calibration file (parseDataset: JSON through nlohmann::json, then
// every field's checks, docs/dataset.md), and writing back what it accepts (formatDataset),
// which must parse again.
//
// The input is dataset.json text. Files it names are not opened (validateDatasetFiles would read
// whatever path the input names). Seeds: fuzz/seeds/dataset/.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "common/core/error.h"
#include "common/media/dataset.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  tdvo::Dataset dataset;
  try {
    dataset = tdvo::parseDataset(text, "fuzz/dataset.json", "/fuzz");
  } catch (const tdvo::Error&) {
    return 0;
  }
  const std::string written = tdvo::formatDataset(dataset, "/fuzz");
  try {
    tdvo::parseDataset(written, "written/dataset.json", "/fuzz");
  } catch (const tdvo::Error& e) {
    std::fprintf(stderr, "dataset fuzz target: what formatDataset wrote does not parse: %s\n",
                 e.what());
    std::abort();
  }
  return 0;
}

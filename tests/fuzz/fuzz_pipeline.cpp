// libFuzzer harness for the YAML pipeline loader: any text is a valid pipeline or a ConfigError naming
// what is wrong (never a crash, undefined behaviour or another exception). Nothing runs.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "scanmesh/pipeline.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  scanmesh::register_scan_stages();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    (void)scanmesh::Pipeline::parse(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.yaml", {});
  } catch (const scanmesh::Error&) {
  }
  return 0;
}

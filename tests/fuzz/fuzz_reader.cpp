// libFuzzer harness for one reader, chosen at compile time (tests/fuzz/CMakeLists.txt builds one binary
// per format). The contract under test: any bytes give a valid result or a scanmesh::Error (InputError),
// never a crash, a hang, undefined behaviour, another exception or unbounded memory.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "scanmesh/cloud_io.h"
#include "scanmesh/errors.h"
#include "scanmesh/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
#if defined(SCANMESH_FUZZ_MESH)
    (void)scanmesh::decode_mesh(bytes, "fuzz" SCANMESH_FUZZ_MESH);
#elif defined(SCANMESH_FUZZ_CLOUD)
    (void)scanmesh::decode_cloud(bytes, "fuzz" SCANMESH_FUZZ_CLOUD);
#elif defined(SCANMESH_FUZZ_CONF)
    Eigen::Isometry3d pose;
    (void)scanmesh::parse_conf_pose(bytes, "fuzz.conf", "bun000.ply", pose);
#else
#error "define the reader to fuzz"
#endif
  } catch (const scanmesh::Error&) {
  }
  return 0;
}

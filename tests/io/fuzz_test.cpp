// Mutation fuzzing of every reader: truncated files, flipped bytes and random garbage must give a mesh
// that passes validation or an InputError, never a crash, a hang or another exception.
#include <gtest/gtest.h>

#include <random>

#include "helpers.h"
#include "scanmesh/atomic_file.h"
#include "scanmesh/errors.h"
#include "scanmesh/mesh_io.h"

using namespace scanmesh;

namespace {

class ReaderFuzz : public test::TempDirTest {
 protected:
  void fuzz(const std::string& name, const std::string& valid) {
    std::mt19937 rng(static_cast<unsigned>(valid.size()));
    for (int round = 0; round < 150; ++round) {
      std::string bytes = valid;
      switch (round % 3) {
        case 0:  // truncate
          bytes.resize(std::uniform_int_distribution<std::size_t>(0, bytes.size())(rng));
          break;
        case 1:  // flip a few bytes
          for (int k = 0; k < 4 && !bytes.empty(); ++k)
            bytes[std::uniform_int_distribution<std::size_t>(0, bytes.size() - 1)(rng)] = static_cast<char>(rng());
          break;
        default:  // replace a digit run with a huge or negative number
          if (const auto p = bytes.find_first_of("123456789", std::uniform_int_distribution<std::size_t>(0, bytes.size())(rng));
              p != std::string::npos)
            bytes.replace(p, 1, round % 2 ? "99999999999" : "-7");
      }
      const std::string file = write(name, bytes);
      try {
        const Mesh m = read_mesh(file);
        validate_mesh(m, file);  // a mesh that loads must be valid
      } catch (const InputError&) {
        // a clear error is fine
      } catch (const std::exception& e) {
        ADD_FAILURE() << name << " round " << round << ": unexpected exception " << e.what();
      }
    }
  }
};

}  // namespace

TEST_F(ReaderFuzz, AllMeshReadersSurviveMutations) {
  const Mesh m = test::make_sphere(1);
  for (const std::string ext : {".obj", ".off", ".ply", ".stl"})
    for (bool binary : {false, true}) {
      WriteOptions w;
      w.binary = binary;
      write_mesh(m, path("valid" + ext), w);
      fuzz("fuzz" + ext, read_file(path("valid" + ext)));
    }
}

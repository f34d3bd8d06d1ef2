#include "scanmesh/atomic_file.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>

#include "helpers.h"
#include "scanmesh/errors.h"

using namespace scanmesh;
namespace fs = std::filesystem;

namespace {

class AtomicFile : public test::TempDirTest {
 protected:
  // Hidden temporaries in the test folder.
  std::vector<std::string> temporaries() const {
    std::vector<std::string> t;
    for (const auto& e : fs::directory_iterator(dir_))
      if (e.path().filename().string().find(".tmp.") != std::string::npos) t.push_back(e.path().string());
    return t;
  }
  // Forks a child that writes `target` in a transaction and then receives `sig` before committing.
  int killed_while_writing(const std::string& target, int sig) const {
    const pid_t pid = ::fork();
    if (pid == 0) {
      OutputTransaction t;
      t.write(target, std::string(1 << 20, 'x'));
      ::raise(sig);
      ::_exit(0);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    return WIFSIGNALED(status) ? WTERMSIG(status) : -1;
  }
};

}  // namespace

TEST_F(AtomicFile, NothingIsVisibleBeforeCommitAndAllOfItAfter) {
  OutputTransaction t;
  t.write(path("a.txt"), "first");
  t.write(path("b.txt"), "second");
  t.write(path("a.txt"), "first, again");  // replaces the earlier write
  EXPECT_FALSE(fs::exists(path("a.txt")));
  EXPECT_EQ(temporaries().size(), 2u);
  t.commit();
  EXPECT_EQ(read_file(path("a.txt")), "first, again");
  EXPECT_EQ(read_file(path("b.txt")), "second");
  EXPECT_TRUE(temporaries().empty());
}

TEST_F(AtomicFile, AnAbandonedTransactionLeavesNothing) {
  {
    OutputTransaction t;
    t.write(path("a.txt"), "data");
  }
  EXPECT_FALSE(fs::exists(path("a.txt")));
  EXPECT_TRUE(temporaries().empty());
}

TEST_F(AtomicFile, SignalsRemoveTemporaries) {
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    EXPECT_EQ(killed_while_writing(path("out.ply"), sig), sig);
    EXPECT_TRUE(temporaries().empty()) << "signal " << sig;
    EXPECT_FALSE(fs::exists(path("out.ply")));
  }
}

TEST_F(AtomicFile, TemporariesOfAKilledRunAreRemovedByTheNextWrite) {
  EXPECT_EQ(killed_while_writing(path("out.ply"), SIGKILL), SIGKILL);
  ASSERT_EQ(temporaries().size(), 1u);  // SIGKILL cannot be caught...
  EXPECT_FALSE(fs::exists(path("out.ply")));  // ...but it leaves nothing under the output's name
  write_file_atomically(path("out.ply"), "fresh");
  EXPECT_TRUE(temporaries().empty());  // the dead run's temporary is gone
  EXPECT_EQ(read_file(path("out.ply")), "fresh");
}

TEST_F(AtomicFile, MissingOrReadOnlyFoldersFailBeforeWriting) {
  EXPECT_THROW(check_writable(path("none/out.ply")), OutputError);
  EXPECT_THROW(write_file_atomically(path("none/out.ply"), "x"), OutputError);
  EXPECT_THROW(check_writable(dir_.string()), OutputError);  // a folder is not a file to write
  EXPECT_NO_THROW(check_writable(path("out.ply")));
}

TEST_F(AtomicFile, AStreamedFileIsWrittenPieceByPieceAndAFailedOneLeavesNothing) {
  OutputTransaction t;
  t.write_with(path("s.txt"), [](const ByteSink& sink) {
    for (int i = 0; i < 1000; ++i) sink(std::to_string(i) + ",");
  });
  t.commit();
  std::string expected;
  for (int i = 0; i < 1000; ++i) expected += std::to_string(i) + ",";
  EXPECT_EQ(read_file(path("s.txt")), expected);
  // A producer that fails half way: no file, no temporary, the error as it was thrown.
  EXPECT_THROW(write_file_atomically(path("f.txt"),
                                     [](const ByteSink& sink) {
                                       sink("half");
                                       throw InputError("the data ran out");
                                     }),
               InputError);
  EXPECT_FALSE(fs::exists(path("f.txt")));
  EXPECT_TRUE(temporaries().empty());
}

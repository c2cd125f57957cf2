// runBounded (bounded_child.hpp): work in a forked child under the memory and CPU budget of a
// file. The same refusals in the release and the sanitizer build: there the budget is
// RLIMIT_DATA and AddressSanitizer's out-of-memory report reaches the parent as exhausted
// memory (one large allocation, or many small ones from the sanitizer's primary allocator;
// there the limit is twice the budget plus 512 MiB for quarantine and redzones).
#include <gtest/gtest.h>

#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "error_matchers.hpp"
#include "taskmap/core/bounded_child.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

using taskmap::testing::errorMessage;

std::string outcome(const std::function<std::string()>& work) {
  try {
    return "returned " + runBounded(work, 100, "file 'x.obj'");
  } catch (const Error& e) {
    return e.what();
  }
}

TEST(BoundedChild, ResultComesBackAndTheBudgetIsNamed) {
  EXPECT_EQ(outcome([] { return std::string("triangles\0bytes", 15); }),
            "returned " + std::string("triangles\0bytes", 15));
  const ParseBudget b = parseBudget(100);
  EXPECT_EQ(b.memory_bytes, 256ull << 20);
  EXPECT_EQ(parseBudget(100ull << 20).memory_bytes, 2000ull << 20);
}

TEST(BoundedChild, WithinTheBudgetIsFine) {
  EXPECT_EQ(outcome([] {
              std::vector<char> v(100u << 20, 1);
              return std::to_string(v[12345]);
            }),
            "returned 1");
}

TEST(BoundedChild, OneLargeAllocationOverTheBudgetIsRefusedAsMemory) {
  const std::string e = outcome([] {
    std::vector<char> v(3ull << 30, 1);
    return std::to_string(v[5]);
  });
  EXPECT_EQ(e.rfind("file 'x.obj': needs more than 256 MiB of memory to parse; refused", 0), 0u)
      << e;
}

TEST(BoundedChild, ManySmallAllocationsOverTheBudgetAreRefusedAsMemory) {
  const std::string e = outcome([] {
    std::vector<std::unique_ptr<char[]>> blocks;
    for (int i = 0; i < 32768; ++i) {  // 2 GiB in 64 KiB blocks
      blocks.emplace_back(new char[65536]);
      blocks.back()[0] = 1;
    }
    return std::to_string(blocks.size());
  });
  EXPECT_EQ(e.rfind("file 'x.obj': needs more than 256 MiB of memory to parse; refused", 0), 0u)
      << e;
}

TEST(BoundedChild, ExceptionsComeBackWithTheirMessage) {
  EXPECT_EQ(outcome([]() -> std::string { throw Error("file 'x.obj': line 3 is not a vertex"); }),
            "file 'x.obj': line 3 is not a vertex");
}

TEST(BoundedChild, CrashOfTheWorkIsARefusal) {
  const std::string e = outcome([] {
    std::abort();
    return std::string();
  });
  EXPECT_EQ(e.rfind("file 'x.obj': the parser crashed", 0), 0u) << e;
}

// Explicit limits (`taskmap import` and `seal`'s --memory-gib and --cpu-seconds): the limits are
// named as given; zero limits are a caller's mistake.
TEST(BoundedChild, ExplicitLimitsAreNamedAsGiven) {
  const ParseBudget limits{300ull << 20, 5};
  const auto run = [&](const std::function<std::string()>& work) {
    try {
      return "returned " + runBounded(work, limits, "cannot import 'g.h5'");
    } catch (const Error& e) {
      return std::string(e.what());
    }
  };
  EXPECT_EQ(run([] { return std::string("wrote 3 grasps"); }), "returned wrote 3 grasps");
  const std::string e = run([] {
    std::vector<char> v(3ull << 30, 1);
    return std::to_string(v[5]);
  });
  EXPECT_EQ(e.rfind("cannot import 'g.h5': needs more than 300 MiB of memory to parse; refused "
                    "(the limits are 300 MiB of memory and 5 s of CPU)",
                    0),
            0u)
      << e;
  EXPECT_EQ(run([]() -> std::string { throw Error("grasps/transforms is missing"); }),
            "grasps/transforms is missing");
  EXPECT_EQ(errorMessage([] {
              runBounded([] { return std::string(); }, ParseBudget{0, 5}, "x");
            }),
            "x: the memory and CPU limits must be positive");
}

}  // namespace
}  // namespace taskmap

// Every shipped example validates against its domain (the folder name).
#include <filesystem>

#include <gtest/gtest.h>

#include "test_util.h"

namespace ctb {
namespace {

namespace fs = std::filesystem;

TEST(Examples, EveryShippedStatePlanValidates) {
  int count = 0;
  for (const auto& dir : fs::directory_iterator(testing::ConfigDir() + "/examples")) {
    if (!dir.is_directory()) continue;
    const Domain& domain = testing::ShippedDomain(dir.path().filename().string());
    for (const auto& f : fs::directory_iterator(dir.path())) {
      if (f.path().extension() != ".json") continue;
      Diagnostics d;
      auto j = ReadJsonFile(f.path().string(), d);
      ASSERT_TRUE(j) << f.path();
      EXPECT_TRUE(LoadStatePlan(*j, domain, d)) << f.path() << "\n" << testing::AllErrors(d);
      ++count;
    }
  }
  EXPECT_GE(count, 6);
}

TEST(Examples, ThesisDirectTestPrompt1HasTheFixedIndexWarning) {
  Diagnostics d;
  auto j = ReadJsonFile(testing::ConfigDir() + "/examples/presentation/test1_direct.json", d);
  ASSERT_TRUE(j);
  ASSERT_TRUE(LoadStatePlan(*j, testing::ShippedDomain("presentation"), d));
  ASSERT_EQ(d.warnings().size(), 1u);
  EXPECT_EQ(d.warnings()[0].pointer, "/constraints/temporal/first60/accepting_event1_constraint");
  EXPECT_EQ(d.warnings()[0].offset, 6u);
}

}  // namespace
}  // namespace ctb

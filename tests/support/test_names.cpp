// Linked into every test executable that starts graphs (enact_add_test ... GRAPH): each test
// names itself in the environment (ENACT_TEST_NAME) before it starts anything, so a process
// it leaves behind carries its name, and tests/support/leftovers.sh, run by ctest after the
// last of them, can say which test left it.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

namespace {

class NameEachTest : public ::testing::EmptyTestEventListener {
  void OnTestStart(const ::testing::TestInfo& test) override {
    const std::string name = std::string(test.test_suite_name()) + "." + test.name();
    setenv("ENACT_TEST_NAME", name.c_str(), 1);
  }
};

// registered before main() runs the tests
const bool registered = [] {
  ::testing::UnitTest::GetInstance()->listeners().Append(new NameEachTest);
  return true;
}();

}  // namespace

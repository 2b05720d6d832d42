// TC_VERIFY (core/verify.hpp): an internal invariant checked in every build type, reported as
// an InternalError (not one of the user-facing tc::Error types) naming the source line.
#if !defined(NDEBUG)
#define NDEBUG  // as in Release: the check must not depend on it
#endif
#include <gtest/gtest.h>

#include <string>
#include <type_traits>

#include "tc/core/error.hpp"
#include "tc/core/verify.hpp"

namespace {
int checked_twice(int x) {
  TC_VERIFY(x >= 0, "callers pass a count");
  return 2 * x;
}
}  // namespace

TEST(Verify, ThrowsAnInternalErrorNamingFileAndLine) {
  static_assert(!std::is_base_of_v<tc::Error, tc::InternalError>,
                "an internal error is not a user-facing error");
  int line = 0;
  try {
    line = __LINE__ + 1;
    TC_VERIFY(1 + 1 == 3, "arithmetic as the caller expects it");
    ADD_FAILURE() << "TC_VERIFY did not throw";
  } catch (const tc::InternalError& e) {
    const std::string what = e.what();
    const std::string where = "tests/unit/core_verify_test.cpp:" + std::to_string(line);
    EXPECT_EQ(e.file(), "tests/unit/core_verify_test.cpp");
    EXPECT_EQ(e.line(), line);
    EXPECT_NE(what.find(where), std::string::npos) << what;
    EXPECT_NE(what.find("1 + 1 == 3"), std::string::npos) << what;
    EXPECT_NE(what.find("arithmetic as the caller expects it"), std::string::npos) << what;
  }
}

TEST(Verify, AHoldingConditionPassesAndIsEvaluatedOnce) {
  EXPECT_EQ(checked_twice(4), 8);
  int evaluations = 0;
  TC_VERIFY(++evaluations == 1, "evaluated once");
  EXPECT_EQ(evaluations, 1);
  EXPECT_THROW(checked_twice(-1), tc::InternalError);
}

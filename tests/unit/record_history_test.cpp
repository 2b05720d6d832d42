// physics::History: the columns registered by their components in any order come out in the
// order of docs/case-format.md, the others after them; a standard column without a component,
// or any column registered twice, is an error.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "tc/core/error.hpp"
#include "tc/record/history.hpp"

namespace tc::physics {
namespace {

/// Registers every standard column, last first, each with its position as its value.
void register_standard_backwards(History& h) {
  const auto names = History::standard_columns();
  for (auto i = static_cast<int>(names.size()) - 1; i >= 0; --i)
    h.add(names[static_cast<size_t>(i)], [i] { return static_cast<double>(i); });
}

TEST(History, ColumnsFollowTheFileOrderWhoeverRegistersThem) {
  History h;
  h.add("reaction_a_xmin_x", [] { return -1.0; });
  register_standard_backwards(h);
  h.add("reaction_a_xmax_x", [] { return -2.0; });
  h.record();
  const auto names = History::standard_columns();
  ASSERT_EQ(h.columns().size(), names.size() + 2);
  for (size_t i = 0; i < names.size(); ++i) {
    EXPECT_EQ(h.columns()[i], names[i]);
    EXPECT_EQ(h.row()[i], static_cast<double>(i));
  }
  EXPECT_EQ(h.columns()[0], "step");
  EXPECT_EQ(h.columns()[names.size() - 1], "heat_radiation");
  EXPECT_EQ(h.row()[names.size()], -1.0);
  EXPECT_EQ(h.row()[names.size() + 1], -2.0);
}

TEST(History, AStandardColumnWithoutItsComponentOrTwiceIsAnError) {
  History h;
  h.add("step", [] { return 0.0; });
  EXPECT_THROW(h.record(), Error);
  EXPECT_THROW(h.add("step", [] { return 1.0; }), Error);
}

TEST(History, AnyColumnRegisteredTwiceIsAnError) {
  // Two supports (or pairs) whose names make one column: a reader by name would read the
  // wrong series (issue 42 D7). The case reader refuses such names; this is the last line.
  History h;
  h.add("reaction_a_xmin_ymin_x", [] { return 1.0; });
  EXPECT_THROW(h.add("reaction_a_xmin_ymin_x", [] { return 2.0; }), Error);
  h.add("contact_tangential_force_sum_x", [] { return 1.0; });
  EXPECT_THROW(h.add("contact_tangential_force_sum_x", [] { return 2.0; }), Error);
}

TEST(History, ValueOfReadsTheComponentsCurrentValue) {
  History h;
  register_standard_backwards(h);
  int step = 3;
  double work = 0.5;
  h.add("a", History::value_of(step));
  h.add("b", History::value_of(work));
  h.record();
  step = 4;
  work = 1.5;
  h.record();
  EXPECT_EQ(h["a"], 4.0);
  EXPECT_EQ(h["b"], 1.5);
}

}  // namespace
}  // namespace tc::physics

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "tc/core/error.hpp"
#include "tc/core/numeric/petsc.hpp"
#include "tc/core/table.hpp"

using tc::core::TemperatureTable;
using tc::core::TimeTable;

TEST(TimeTable, ConstantAndPiecewiseLinear) {
  const TimeTable c(2.5);
  EXPECT_EQ(c(-1.0), 2.5);
  EXPECT_EQ(c(1e9), 2.5);
  const TimeTable t({0.0, 0.2, 1.0}, {0.0, 0.0, 0.05});
  EXPECT_DOUBLE_EQ(t(0.1), 0.0);
  EXPECT_DOUBLE_EQ(t(0.6), 0.025);  // halfway between 0.2 and 1.0
  EXPECT_DOUBLE_EQ(t(5.0), 0.05);   // constant beyond the end
  EXPECT_DOUBLE_EQ(t(-5.0), 0.0);   // and before the start
}

TEST(TemperatureTable, PiecewiseLinearInThetaConstantBeyondItsEnds) {
  const TemperatureTable f({300.0, 400.0, 600.0}, {0.5, 0.3, 0.1});
  EXPECT_FALSE(f.is_constant());
  EXPECT_DOUBLE_EQ(f(350.0), 0.4);  // halfway in the first segment
  EXPECT_DOUBLE_EQ(f(500.0), 0.2);  // and in the second
  EXPECT_EQ(f(400.0), 0.3);         // at a table point: its value
  EXPECT_EQ(f(100.0), 0.5);         // constant below the first temperature
  EXPECT_EQ(f(1e4), 0.1);           // and above the last
  EXPECT_EQ(f.max_value(), 0.5);
  EXPECT_EQ(f.min_value(), 0.1);
}

TEST(TemperatureTable, OnePointAndFlatTablesAreTheConstantItself) {
  // A flat table interpolates (1 − s)v + sv, which need not be v in floating point: it is
  // stored as the constant, so the law runs exactly as the number would.
  const double v = 0.1 + 0.2;  // not a short binary fraction
  for (const TemperatureTable& t :
       {TemperatureTable({350.0}, {v}), TemperatureTable({300.0, 333.0, 400.0}, {v, v, v})}) {
    EXPECT_TRUE(t.is_constant());
    EXPECT_TRUE(t.temperatures().empty());
    for (const double theta : {1.0, 300.0, 317.3, 399.9, 1e4}) EXPECT_EQ(t(theta), v);
  }
  EXPECT_TRUE(TemperatureTable(v).is_constant());
  EXPECT_EQ(TemperatureTable(v)(123.0), v);
}

TEST(Petsc, ErrorsBecomeExceptionsNamingTheCall) {
  tc::core::Vector v(3);
  tc::core::Vector w(4);
  try {
    v.axpy(1.0, w);  // incompatible sizes
    FAIL() << "expected a PetscError";
  } catch (const tc::PetscError& e) {
    EXPECT_NE(std::string(e.what()).find("VecAXPY"), std::string::npos) << e.what();
  }
}

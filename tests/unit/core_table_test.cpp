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

TEST(TemperatureTable, IntegralAndSlopeOfThePiecewiseLinearLaw) {
  // v: 2 at 300, 4 at 400, 1 at 600 K; 2 below, 1 above. Integrals by hand (trapezoids and
  // rectangles): exact in binary up to the round-off of the sums (~1e-15 relative).
  const TemperatureTable f({300.0, 400.0, 600.0}, {2.0, 4.0, 1.0});
  const auto near = [](double a, double b) { EXPECT_NEAR(a, b, 1e-13 * std::abs(b)) << a; };
  near(f.integral(300.0, 400.0), 300.0);  // ½(2 + 4)·100
  near(f.integral(350.0, 500.0), 0.5 * (3 + 4) * 50 + 0.5 * (4 + 2.5) * 100);
  near(f.integral(200.0, 700.0), 200.0 + 300.0 + 500.0 + 100.0);  // 2·100 + … + 1·100
  near(f.integral(500.0, 350.0), -(0.5 * (3 + 4) * 50 + 0.5 * (4 + 2.5) * 100));
  EXPECT_EQ(f.integral(320.0, 320.0), 0.0);
  near(TemperatureTable(3.0).integral(10.0, 20.0), 30.0);
  near(f.integral(350.0, 380.0), 0.5 * (3.0 + 3.6) * 30);  // inside one segment
  EXPECT_EQ(f.slope(350.0), 0.02);
  EXPECT_EQ(f.slope(400.0), -0.015);  // the upper segment at a table point
  EXPECT_EQ(f.slope(299.0), 0.0);
  EXPECT_EQ(f.slope(600.0), 0.0);
  EXPECT_EQ(TemperatureTable(3.0).slope(350.0), 0.0);
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

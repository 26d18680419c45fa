// The render loop's --time rule (passes/render_loop.h): it ends at the batch end nearest the budget.
#include "passes/render_loop.h"

#include <gtest/gtest.h>

namespace bp {
namespace {

TEST(RenderLoop, StopsAtTheBatchEndNearestTheTimeBudget) {
  EXPECT_FALSE(time_budget_spent(0.0, 16.0, 0.0));    // nothing predicted yet: the first batch runs
  EXPECT_FALSE(time_budget_spent(0.0, 16.0, 29.0));   // 13 s past beats 16 s short
  EXPECT_TRUE(time_budget_spent(15.8, 16.0, 15.8));   // one round done: a second would end 15.6 s past
  EXPECT_TRUE(time_budget_spent(10.0, 16.0, 12.5));   // 6.5 s past against 6 s short
  EXPECT_FALSE(time_budget_spent(10.0, 16.0, 11.5));  // 5.5 s past against 6 s short
  EXPECT_FALSE(time_budget_spent(15.9, 16.0, 0.1));   // short batches run to the budget
  EXPECT_TRUE(time_budget_spent(16.0, 16.0, 0.0));    // at the budget
  EXPECT_TRUE(time_budget_spent(20.0, 16.0, 0.0));
}

}  // namespace
}  // namespace bp

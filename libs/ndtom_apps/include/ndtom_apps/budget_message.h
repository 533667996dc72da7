// A memory-budget error as the programs word it: the core names its option memory_budget,
// the programs --memory-budget, in MB.
#pragma once

#include <string>

#include "ndtom/map/memory_budget.h"

namespace ndtom::apps {

std::string budgetMessage(const ndtom::MemoryBudgetError& error);

}  // namespace ndtom::apps

// A memory-budget error as the mapping programs (ndtom-map, ndtom-map-mpi) word it: the core
// names its option memory_budget, they --memory-budget, in MB.
#pragma once

#include <string>

#include "ndtom/map/memory_budget.h"

namespace ndtom::apps {

std::string budgetMessage(const ndtom::MemoryBudgetError& error);

}  // namespace ndtom::apps

#include "ndtom_apps/budget_message.h"

namespace ndtom::apps {

std::string budgetMessage(const ndtom::MemoryBudgetError& error) {
  std::string what = error.what();
  const std::string core = "(memory_budget)";
  const size_t at = what.rfind(core);
  if (at != std::string::npos) what.replace(at, core.size(), "(--memory-budget, in MB)");
  return what;
}

}  // namespace ndtom::apps

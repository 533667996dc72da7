#include "localization/refused_registration.h"

#include <sstream>

namespace ndtom::tracking {

namespace {

double matchedShare(const RegistrationResult& r) { return r.matched_fraction * r.judged_fraction; }

}  // namespace

bool replacesRefused(RegistrationResult& candidate,
                     const std::optional<RegistrationResult>& refused, const char* what) {
  if (!refused) return true;
  if (candidate.score >= refused->score && matchedShare(candidate) >= matchedShare(*refused))
    return true;
  std::ostringstream why;
  why << what << " pose fits the map less than the prediction's, which only the free-space "
      << "check refused (score " << candidate.score << " against " << refused->score
      << ", matched " << matchedShare(candidate) << " of the scan against "
      << matchedShare(*refused) << ")";
  candidate.converged = false;
  candidate.failure = why.str();
  return false;
}

}  // namespace ndtom::tracking

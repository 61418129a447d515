#include "results/provenance.hpp"

namespace ajx::results {

std::string program_version() { return ASTROJAX_VERSION; }
std::string program_commit() { return ASTROJAX_GIT_COMMIT; }

}  // namespace ajx::results

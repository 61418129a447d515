#include "results/provenance.hpp"

#include "source_commit.hpp"  // generated: ASTROJAX_GIT_COMMIT, ASTROJAX_COMMIT_ORIGIN

namespace ajx::results {

std::string program_version() { return ASTROJAX_VERSION; }
std::string program_commit() { return ASTROJAX_GIT_COMMIT; }
std::string program_commit_origin() { return ASTROJAX_COMMIT_ORIGIN; }

}  // namespace ajx::results

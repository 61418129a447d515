// /basins of a sweep file (docs/reference/file-format.md), written only when the sweep has basin
// chains (sweep/basin.hpp): every sample's start, final class and features, and per level the
// count, fraction and 95 % Wilson interval of each class. The layout and the starts are written
// when the file is made; the classes, features and fractions are read off /windows when the
// sweep finishes (or is interrupted, over the samples done) and again by `astrojax classify`.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "io/hdf5_file.hpp"
#include "sweep/basin.hpp"
#include "sweep/plan.hpp"

namespace ajx::results {

// The features that tell orbits apart (and match them across levels): /windows statistics.
inline constexpr const char* kBasinFeatures[] = {"omega_ball", "radius_bead_mean", "radius_bottom_mean", "L1_mean"};
inline constexpr std::size_t kNumBasinFeatures = std::size(kBasinFeatures);

// Whether the plan has basin chains.
bool has_basins(const sweep::SweepPlan& plan);

// /basins with every start, the level table and the results "not computed" (class -1, NaN).
void write_basin_layout(io::File& f, const config::SweepConfig& cfg, const sweep::SweepPlan& plan);

// basin.state's orbit (config::StoredOrbitReader): the state at the end of window `window` of
// chain `chain` of the sweep file `path`, read through the one reader (which validates the whole
// file), turned so that the top is at azimuth 0. Throws std::runtime_error naming the file and
// what is wrong: no such chain or window, a window not computed or failed, or one that does not
// end its task (its end state is not stored).
sweep::StoredOrbit read_stored_orbit(const std::string& path, long chain, long window);

// /basins' results from /windows: each sample's class and features, each level's counts,
// fractions and intervals. Nothing when the file has no /basins.
void write_basin_results(io::File& f);

}  // namespace ajx::results

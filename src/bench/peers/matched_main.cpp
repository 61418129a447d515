// astrojax_matched: the two matched comparisons of the work-precision study, in one process
// with interleaved timings (docs/reports/matched-comparison.md).
//  - with the guarantee: the project's default (dop853, rotating axes, max_step = "auto",
//    event_samples = 3) against the hand-written peers given the same guarantee (steps capped
//    at (k+1)/Ω, guards sampled at the same interior points);
//  - without it: the project with event_samples = 0 and no step bound from the guards,
//    against the hand-written peers with a step-end sign check, CVODE Adams with
//    CVodeRootInit and ARKODE's ERKStep (Fehlberg 7(8)) with ERKStepRootInit on the same guards.
// The peers integrate their own right-hand side (bench/peers/hand_model.hpp); the driver first
// prints how far it is from the project's at the scene's start and at the reference's end.
// Every (method, rtol) is timed once per round, rounds interleaved, so that load on the shared
// machine hits all alike; the table keeps the MINIMUM CPU time over the rounds (the median is
// in the CSV). With --warm N each timed run follows N untimed runs of the same point, so that it
// starts with warm caches, as every task of a long sweep does. Built only with -DASTROJAX_PEERS=ON.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fmt/format.h>
#include <fstream>
#include <functional>
#include <map>

#include "bench/peers/cvode_peer.hpp"
#include "bench/peers/hand_bridge.hpp"
#include "bench/peers/hand_model.hpp"
#include "bench/peers/hybrid_peer.hpp"
#include "bench/matched_table.hpp"
#include "bench/scene_file.hpp"
#include "bench/work_precision.hpp"
#include "physics/rotating_axes.hpp"

namespace {

using namespace ajx;
using bench::phase;
using bench::hand_contact;
using bench::project_mode;
using bench::hand_params;
using bench::rhs_mismatch;
namespace odeint = boost::numeric::odeint;

// One method: runs the scene at rtol, returns the final state in the lab axes.
struct Result {
  physics::State final;
  long evals = 0;
  std::string status;
};
using Method = std::function<Result(double rtol)>;

struct Entry {
  std::string name, family;  // family: "guarantee" or "no guarantee"
  Method run;
};

// A peer on the scene: its options from the scene's run options, its start state in the
// rotating axes, its final state back in the lab axes for bench::compare.
using Runner = std::function<hand::PeerRun(hand::Contact c, const hand::Y& y0, double t0, double t1,
                                           const hand::PeerOptions& o)>;
Method peer_method(const bench::Scene& s, bool guarantee, Runner run) {
  return [&s, guarantee, run](double rtol) {
    hand::PeerOptions o;
    o.rtol = rtol;
    o.guarantee = guarantee;
    o.samples = s.run.integ.event_samples;
    o.projection_tol = s.run.projection_tol;
    numerics::Vec y = s.initial.y;
    physics::rotate_about_z(y, -phase(s, s.initial.t));
    hand::Y y0;
    std::copy(y.data(), y.data() + 12, y0.begin());
    const double t1 = s.initial.t + s.horizon;
    const hand::PeerRun r = run(hand_contact(s.initial.contact), y0, s.initial.t, t1, o);
    Result out{s.initial, r.evals, r.status};
    std::copy(r.y.begin(), r.y.end(), out.final.y.data());
    physics::rotate_about_z(out.final.y, phase(s, t1));
    out.final.t = t1;
    out.final.contact = physics::Contact(project_mode(r.contact.mode), r.contact.sigma, r.contact.s_star);
    return out;
  };
}

template <class Controlled>
Method hand_method(const bench::Scene& s, const hand::Params& h, bool guarantee, std::function<Controlled(double)> make) {
  return peer_method(s, guarantee, [&s, h, make](hand::Contact c, const hand::Y& y0, double t0, double t1,
                                                  const hand::PeerOptions& o) {
    return hand::run_peer(h, c, y0, t0, t1, make(o.rtol), o, s.schedule.breakpoints());
  });
}

// A SUNDIALS peer: run_cvode_adams or run_arkode_f78.
template <class Run>
Method sundials_method(const bench::Scene& s, const hand::Params& h, bool guarantee, Run solver) {
  return peer_method(s, guarantee, [&s, h, solver](hand::Contact c, const hand::Y& y0, double t0, double t1,
                                                   const hand::PeerOptions& o) {
    return solver(h, c, y0, t0, t1, o, s.schedule.breakpoints());
  });
}

Method project_method(const bench::Scene& scene, bool guarantee) {
  bench::Scene s = scene;
  // As a sweep runs it: the peers return the final state only, so the project computes no run
  // statistics (ω_ball, the samples' extremes) either; their cost is BM_run/…_statistics.
  s.run.run_statistics = false;
  if (!guarantee) {  // event_samples = 0 and no step bound from the guards (h ≤ 10 s only)
    s.run.guard_step_bound = false;
    s.run.integ.event_samples = 0;
  }
  return [s](double rtol) {
    const bench::Outcome o = bench::run_point(s, {"dop853", rtol, 0.0}, 1, 0.0);
    return Result{o.final, o.rhs_evals, o.status};
  };
}

std::vector<Entry> methods(const bench::Scene& s, const hand::Params& h) {
  using Y = hand::Y;
  using Dopri5 = odeint::controlled_runge_kutta<odeint::runge_kutta_dopri5<Y>>;
  using Rkf78 = odeint::controlled_runge_kutta<odeint::runge_kutta_fehlberg78<Y>>;
  using Bs = odeint::bulirsch_stoer<Y>;
  const std::function<Dopri5(double)> dopri5 = [](double r) {
    return odeint::make_controlled(1e-3 * r, r, odeint::runge_kutta_dopri5<Y>());
  };
  const std::function<Rkf78(double)> rkf78 = [](double r) {
    return odeint::make_controlled(1e-3 * r, r, odeint::runge_kutta_fehlberg78<Y>());
  };
  const std::function<Bs(double)> bs = [](double r) { return Bs(1e-3 * r, r); };
  std::vector<Entry> out;
  for (bool g : {true, false}) {
    const std::string fam = g ? "guarantee" : "no guarantee";
    out.push_back({g ? "astrojax dop853 (default)" : "astrojax dop853 (k=0, no bound)", fam, project_method(s, g)});
    out.push_back({"hand odeint rkf78", fam, hand_method<Rkf78>(s, h, g, rkf78)});
    out.push_back({"hand odeint dopri5", fam, hand_method<Dopri5>(s, h, g, dopri5)});
    out.push_back({"hand odeint bulirsch-stoer", fam, hand_method<Bs>(s, h, g, bs)});
    out.push_back({"hand CVODE Adams + CVodeRootInit", fam, sundials_method(s, h, g, hand::run_cvode_adams)});
    out.push_back({"hand ARKODE ERK f78 + ERKStepRootInit", fam, sundials_method(s, h, g, hand::run_arkode_f78)});
  }
  return out;
}

}  // namespace

// Long for a reason: a benchmark driver read top to bottom (options, then scenes x horizons x
// interleaved rounds into one CSV and the tables), like the astrojax bench it mirrors.
int main(int argc, char** argv) {
  CLI::App app{"astrojax_matched: the project against hand-written peers, with and without the event guarantee"};
  std::vector<std::string> paths, overrides;
  std::string output = "out/matched.csv";
  std::vector<double> horizons{10.0, 100.0}, targets{1e-6, 1e-9};
  std::vector<double> rtols{1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12};
  int rounds = 5;
  int warm = 0;
  app.add_option("scenes", paths, "Run files (sweeps/scenes/*.toml)")->required();
  app.add_option("-o,--output", output, "CSV output path")->capture_default_str();
  app.add_option("-s,--set", overrides, "Override a key in every scene");
  app.add_option("--horizons", horizons, "Error measured at these times [s]")->delimiter(',');
  app.add_option("--targets", targets, "Position errors of the tables [m]")->delimiter(',');
  app.add_option("--rtols", rtols, "Relative tolerances (atol = 1e-3 rtol)")->delimiter(',');
  app.add_option("--rounds", rounds, "Interleaved timing rounds (the minimum is kept)")->capture_default_str();
  app.add_option("--warm", warm, "Untimed runs of each point just before its timed run in every round "
                 "(0: the timed run starts with caches holding the previous method's code and data)")
      ->capture_default_str()
      ->check(CLI::Range(0, 100));
  CLI11_PARSE(app, argc, argv);

  std::ofstream csv(output);
  std::vector<bench::MatchedPoint> all;
  csv << bench::matched_csv_header() << "\n";
  for (const std::string& path : paths) {
    for (double horizon : horizons) {
      bench::Scene scene;
      hand::Params h;
      try {
        scene = bench::load_scene(path, overrides, horizon);
        h = hand_params(scene);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 2;
      }
      const bench::Reference ref = bench::reference(scene);
      std::printf("%s, %g s: reference %ld mode switches, final %s, floor %.1e m; hand RHS against the project's: "
                  "%.1e at the start, %.1e at the end (relative)\n",
                  scene.name.c_str(), horizon, ref.run.mode_switches,
                  std::string(physics::to_string(ref.run.final.contact.mode)).c_str(), ref.floor,
                  rhs_mismatch(scene, h, scene.initial), rhs_mismatch(scene, h, ref.run.final));
      const bench::RhsCost cost = bench::rhs_cost(scene, h, scene.initial);
      std::printf("  one right-hand-side evaluation at the start: project %.0f ns, hand-written peer %.0f ns\n",
                  1e9 * cost.project, 1e9 * cost.hand);
      std::fflush(stdout);
      const std::vector<Entry> entries = methods(scene, h);
      std::vector<bench::MatchedPoint> points;
      for (const Entry& e : entries)
        for (double r : rtols) {
          bench::MatchedPoint pt;
          pt.scene = scene.name;
          pt.horizon = horizon;
          pt.method = e.name;
          pt.family = e.family;
          pt.rtol = r;
          points.push_back(pt);
        }
      for (int round = 0; round < rounds; ++round) {
        std::size_t i = 0;
        for (const Entry& e : entries)
          for (double r : rtols) {
            bench::MatchedPoint& pt = points[i++];
            if (round > 0 && pt.status != "ok") continue;
            for (int k = 0; k < warm; ++k) e.run(r);  // warm: the same run, untimed
            const double c0 = bench::cpu_seconds();
            const Result res = e.run(r);
            pt.cpu.push_back(bench::cpu_seconds() - c0);
            if (round == 0) {
              pt.status = res.status;
              pt.evals = res.evals;
              const bench::Errors err = bench::compare(res.final, ref.run.final);
              pt.error = err.position;
              pt.same_mode = err.same_mode;
            }
          }
      }
      for (const bench::MatchedPoint& pt : points) csv << bench::matched_csv_line(pt, ref.floor) << "\n";
      csv.flush();
      std::printf("%s", bench::matched_tables(points, targets).c_str());
      std::fflush(stdout);
      all.insert(all.end(), points.begin(), points.end());
    }
  }
  std::printf("\nSummary (peer CPU / astrojax CPU, minimum over rounds; > 1: astrojax faster):\n%s",
              bench::matched_summary(all, targets).c_str());
  std::printf("-> %s\n", output.c_str());
  return 0;
}

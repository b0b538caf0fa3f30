// brdf measure --sample SAMPLE [--schedule S] [--instrument J] [--seed N] [--threads N]
// [--quiet] --out FILE: the virtual gonioreflectometer (DESIGN §5). Native CSV with sigma
// columns, or MERL .binary when the schedule is `merl`. Under mpirun the incidences are split
// across the ranks and rank 0 writes the file (DESIGN §11).
#include <tbb/global_control.h>

#include <iostream>
#include <memory>
#include <optional>

#include "cli/commands.h"
#include "core/errors.h"
#include "core/parallel_ranks.h"
#include "core/progress.h"
#include "gonio/instrument.h"
#include "gonio/measure.h"
#include "gonio/schedule.h"
#include "io/formats.h"

namespace brdf::cli {

Command AddMeasureCommand(CLI::App& parent) {
  struct Options {
    std::string sample, schedule = "hemisphere", instrument, out;
    uint64_t seed = 1;
    int threads = 0;
    bool quiet = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand(
      "measure", "Simulate a gonioreflectometer measurement of a sample (virtual instrument)");
  app->footer(
      "Under mpirun the incidence directions are split across the ranks; rank 0 writes the file, "
      "byte for byte the one a run without mpirun writes (--threads then applies per rank).");
  app->add_option("--sample", options->sample,
                  "model:MODEL (flat analytic sample; MODEL is a model string or FIT.json), "
                  "surface:FILE.json (ray-traced micro-geometry, see data/surfaces/; its "
                  "heightfield's rms_slope is the Gaussian field's slope, Beckmann's alpha, and "
                  "rms_slope_y, default rms_slope, makes it anisotropic: rms_slope along x, "
                  "rms_slope_y along y) or "
                  "sphere:MODEL (image-based: a camera views a rasterized sphere)")
      ->required();
  app->add_option("--schedule", options->schedule,
                  "inplane[:step=D] | hemisphere[:theta_i_step=D:theta_o_step=D:phi_o_step=D] | "
                  "merl | equal-area:cells=N[:theta_i_step=D] | "
                  "adaptive[:theta_i_step=D:base_step=D] | uniform:count=N[:theta_max=D] | "
                  "file:PLAN.csv (a CSV whose header names theta_i,phi_i,theta_o,phi_o, e.g. from "
                  "brdf plan) (degrees; steps default 5, base_step 10)")
      ->capture_default_str();
  app->add_option("--instrument", options->instrument,
                  "instrument JSON (every field optional; default: collimated source of 0.25 deg "
                  "radius, 1e-3 sr detector, 1e6 reference counts, read noise 10, jitter "
                  "0.05 deg, no stray light, Lambertian reference rho=0.99 at 0/45 deg, camera "
                  "128x128 px at 10 sphere radii; see docs/gonio.md)");
  app->add_option("--seed", options->seed, "random seed; equal seeds give identical files")
      ->capture_default_str();
  app->add_option("--threads", options->threads,
                  "worker threads (0 = all cores); the output does not depend on it")
      ->capture_default_str()
      ->check(CLI::Range(0, 1024));
  app->add_flag("--quiet", options->quiet, "no progress bar on stderr");
  app->add_option("--out", options->out,
                  "output measurement: native CSV (.csv, with sigma columns), or MERL .binary "
                  "(with, and only with, the merl schedule)")
      ->required();

  return {app,
          [options]() {
            std::optional<tbb::global_control> thread_limit;
            if (options->threads > 0) {
              thread_limit.emplace(tbb::global_control::max_allowed_parallelism,
                                   static_cast<size_t>(options->threads));
            }
            gonio::MeasureOptions measure;
            measure.sample = options->sample;
            measure.schedule = options->schedule;
            measure.seed = options->seed;
            if (!options->instrument.empty()) {
              measure.instrument = gonio::ReadInstrument(options->instrument);
              measure.instrument_name = options->instrument;
            }
            const gonio::Schedule schedule = gonio::MakeSchedule(options->schedule);
            const FileFormat& output_format = OutputFormat(options->out);
            if (schedule.fixed_grid != output_format.fixed_grid) {
              throw UsageError(options->out +
                               ": the merl schedule and MERL .binary output go together "
                               "(--schedule merl --out FILE.binary)");
            }
            Progress progress("measuring", gonio::CountReadings(measure, schedule),
                              options->quiet || !ranks::IsRoot());
            measure.advance = [&progress](int64_t done) { progress.Advance(done); };
            const Measurement measurement = gonio::Measure(measure, schedule);
            if (!ranks::IsRoot()) return 0;  // rank 0 gathered every rank's readings
            const WriteReport report =
                WriteMeasurement(measurement, options->out, output_format.name);
            for (const std::string& warning : report.warnings) {
              std::cerr << "brdf measure: warning: " << warning << "\n";
            }
            if (!options->quiet) {
              std::cout << "wrote " << options->out << " (" << output_format.name << ", "
                        << measurement.samples.size() << " samples)\n";
            }
            return 0;
          },
          /*distributed=*/true};
}

}  // namespace brdf::cli

// brdf: measure, fit, check and preview reflectance. Maps typed errors to exit statuses
// (DESIGN §3): 0 success, 2 bad usage or bad input, 3 a computation failed, 1 an internal error.
// Under mpirun every rank runs this (DESIGN §11); see ReportError for who prints what.
#include <malloc.h>

#include <algorithm>
#include <iostream>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "core/errors.h"
#include "core/parallel_ranks.h"

namespace {

// Prints the error (rank 0 prints a job's failure for every rank; the others print only errors
// of their own, naming their rank) and returns the process's exit status. An error outside a
// distributed step may leave the other ranks waiting for this one: the whole job is then ended with
// `status`.
int ReportError(const std::string& message, int status) {
  if (brdf::ranks::Size() == 1) {
    std::cerr << "brdf: " + message + "\n";
    return status;
  }
  if (!brdf::ranks::FailedInStep()) {
    // One write per line, so that the ranks' lines do not interleave.
    std::cerr << "brdf: rank " + std::to_string(brdf::ranks::Rank()) + ": " + message + "\n";
    brdf::ranks::Abort(status);
  }
  if (!brdf::ranks::IsRoot()) {
    // Rank 0 knows this failure too: it prints it once and ends the job with `status`. The other
    // ranks end with 0, because mpirun kills every process still running at the first non-zero
    // exit, and rank 0 may then be cut off while it removes its temporary output or finalizes
    // MPI. The job's status is rank 0's either way.
    return 0;
  }
  std::cerr << "brdf: " + message + "\n";
  return status;
}

// The number of single-character edits (insert, delete, substitute) that turn `a` into `b`.
size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// "unknown command 'fitt' (did you mean 'fit'?)" when the first word that is not an option names
// no command; empty when it does (or there is none).
std::string UnknownCommandMessage(const CLI::App& app, int argc, char** argv) {
  for (int k = 1; k < argc; ++k) {
    const std::string word = argv[k];
    if (word.empty() || word[0] == '-') continue;
    std::string nearest;
    size_t best = word.size();
    for (const CLI::App* command : app.get_subcommands({})) {
      if (command->get_name() == word) return {};
      const size_t distance = EditDistance(word, command->get_name());
      if (distance < best) best = distance, nearest = command->get_name();
    }
    std::string message = "unknown command '" + word + "'";
    // A suggestion only when it is plausibly what was meant: at most half the word retyped.
    if (!nearest.empty() && 2 * best <= word.size())
      message += " (did you mean '" + nearest + "'?)";
    return message + "; run 'brdf --help' for the list of commands";
  }
  return {};
}

}  // namespace

int main(int argc, char** argv) {
  // A 1080p float RGBA image is 33 MB, above glibc's largest mmap threshold (32 MB): every such
  // buffer would be mapped fresh and returned on free, and the kernel's page clearing took over
  // half of the HDR pipeline's time. Serving large blocks from the heap and keeping them lets
  // the pipeline's stages reuse freed memory.
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  const brdf::ranks::Session mpi_session(&argc, &argv);
  CLI::App app{"brdfkit: measure, fit, check and preview reflectance (BRDFs)", "brdf"};
  app.set_version_flag("--version", std::string("brdf ") + BRDFKIT_VERSION);
  app.require_subcommand(1);
  app.footer("Run 'brdf COMMAND --help' for the options of each command.");

  const std::vector<brdf::cli::Command> commands = {
      brdf::cli::AddDemoCommand(app),    brdf::cli::AddInfoCommand(app),
      brdf::cli::AddConvertCommand(app), brdf::cli::AddMeasureCommand(app),
      brdf::cli::AddFitCommand(app),     brdf::cli::AddEnergyCommand(app),
      brdf::cli::AddRenderCommand(app),  brdf::cli::AddTonemapCommand(app),
      brdf::cli::AddBatchCommand(app),   brdf::cli::AddExportCommand(app),
      brdf::cli::AddPlanCommand(app),    brdf::cli::AddViewCommand(app),
  };

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    // --help and --version print and succeed; every other parse error is one "brdf: " line.
    if (error.get_exit_code() == 0) return app.exit(error);
    std::string message = UnknownCommandMessage(app, argc, argv);
    if (message.empty()) {
      const std::vector<CLI::App*> parsed = app.get_subcommands();
      message = parsed.empty() ? std::string(error.what())
                               : parsed[0]->get_name() + ": " + error.what() + " (run 'brdf " +
                                     parsed[0]->get_name() + " --help')";
    }
    std::cerr << "brdf: " << message << "\n";
    return 2;
  }

  try {
    for (const brdf::cli::Command& command : commands) {
      if (!command.app->parsed()) continue;
      if (brdf::ranks::LaunchedByMpi() && !brdf::ranks::BuiltWithMpi()) {
        std::cerr << "brdf: warning: started by mpirun, but this build has no MPI "
                     "(BRDFKIT_MPI=OFF): every process runs the whole job on its own\n";
      }
      if (brdf::ranks::Size() > 1 && !command.distributed) {
        throw brdf::UsageError("'" + command.app->get_name() +
                               "' runs on one process; under mpirun only measure and batch split "
                               "their work across ranks");
      }
      return command.run();
    }
  } catch (...) {
    std::string message;
    const int status = brdf::ExitStatus(std::current_exception(), &message);
    return ReportError(message, status);
  }
  return 2;
}

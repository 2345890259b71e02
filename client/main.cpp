// ctburton: the command-line tool. Thin: every subcommand calls the libraries.
#include <csignal>
#include <iostream>
#include <string>
#include <vector>

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "client/commands.h"
#include "translator/text.h"

namespace ctb::cli {
int ExitCodeFor(ErrorCode code) {
  switch (code) {
    case ErrorCode::kInvalidInput:
    case ErrorCode::kNotFound:
    case ErrorCode::kTooLarge: return 1;
    case ErrorCode::kUnprocessable: return 4;
    default: return 3;
  }
}

void PrintError(const Error& e) {
  std::cerr << "error (" << CodeName(e.code) << "): " << ValidUtf8(e.message) << "\n";
  for (const auto& d : e.details) std::cerr << ValidUtf8(d.ToString()) << "\n";
}

int Fail(const Error& e) {
  PrintError(e);
  return ExitCodeFor(e.code);
}
}  // namespace ctb::cli

int main(int argc, char** argv) {
  // A peer that closes its socket must not kill the process (server and client alike).
  std::signal(SIGPIPE, SIG_IGN);
#ifndef CTB_WITH_SERVER
  if (argc > 1 && std::string(argv[1]) == "serve") return ctb::cli::ExecServer(argv);
#endif
  // Logs go to stderr: stdout carries the JSON answers.
  spdlog::set_default_logger(spdlog::stderr_color_mt("ctburton"));
  spdlog::set_level(spdlog::level::warn);
  CLI::App app{"ctburton: natural language to verified multi-agent plans"};
  app.require_subcommand(1);
  std::vector<ctb::cli::Runner> runners;
  runners.push_back(ctb::cli::AddValidate(app));
  runners.push_back(ctb::cli::AddSolve(app));
  runners.push_back(ctb::cli::AddTranslate(app));
#ifdef CTB_WITH_SERVER
  runners.push_back(ctb::cli::AddServe(app));
#else
  ctb::cli::AddServeEntry(app);
#endif
  runners.push_back(ctb::cli::AddPlan(app));
  runners.push_back(ctb::cli::AddEval(app));
  runners.push_back(ctb::cli::AddSchema(app));
  runners.push_back(ctb::cli::AddReplan(app));
  runners.push_back(ctb::cli::AddExecute(app));
  runners.push_back(ctb::cli::AddDomain(app));
  runners.push_back(ctb::cli::AddNetwork(app));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version print and succeed; every other parse error is a usage error: 2.
    int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  }
  for (auto& run : runners) {
    int rc = run();
    if (rc >= 0) return rc;
  }
  return 2;
}

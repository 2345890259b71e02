// `ctburton serve` in the command-line executable: the service lives in ctburton-server (beside
// this executable), which links gRPC, MQTT and the HTTP server. Keeping them out of `ctburton`
// halves what every one-shot command pays to start (bench/results/cli_startup.md).
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <system_error>

#include "client/commands.h"

namespace ctb::cli {

namespace {
std::string ServerBinary() {
  std::error_code ec;
  std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return "ctburton-server";
  return (self.parent_path() / "ctburton-server").string();
}
}  // namespace

int ExecServer(char** argv) {
  std::string path = ServerBinary();
  execv(path.c_str(), argv);
  std::cerr << "error: `ctburton serve` runs " << path << ", which could not be started: "
            << std::strerror(errno) << " (it is built and installed beside ctburton)\n";
  return 3;
}

void AddServeEntry(CLI::App& app) {
  app.add_subcommand("serve",
                     "Run the HTTP service (default 127.0.0.1:8080), and gRPC with --grpc-port "
                     "(runs ctburton-server; `ctburton serve --help` for its options)");
}

}  // namespace ctb::cli

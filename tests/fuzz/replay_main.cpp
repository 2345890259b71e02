// Replays kept fuzz inputs without libFuzzer (docs/reliability.md): the normal build compiles
// every target of tests/fuzz into this one executable, each target's LLVMFuzzerTestOneInput
// renamed to CtbFuzz_<target> by a compile definition, so CI runs every seed and regression input
// with the ordinary compiler.
//
//   fuzz_replay TARGET PATH...   each PATH a file or a folder (read recursively, sorted)
//
// Exit 0 when every input ran, each within kMaxSeconds; a broken invariant traps (the process
// dies), a slow input fails with its name. Prints one line per target: inputs and slowest.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#define CTB_FUZZ_TARGETS(X) \
  X(expr) X(domain) X(state_plan) X(replan) X(translator) X(pddl) X(network) X(grpc_convert)

#define CTB_DECLARE(name) extern "C" int CtbFuzz_##name(const std::uint8_t* data, std::size_t size);
CTB_FUZZ_TARGETS(CTB_DECLARE)
#undef CTB_DECLARE

namespace {

using Target = int (*)(const std::uint8_t*, std::size_t);
constexpr double kMaxSeconds = 1.0;  // the campaign's hang threshold

std::vector<std::filesystem::path> Inputs(const std::vector<std::string>& paths) {
  std::vector<std::filesystem::path> out;
  for (const auto& p : paths) {
    if (std::filesystem::is_directory(p)) {
      for (const auto& e : std::filesystem::recursive_directory_iterator(p))
        if (e.is_regular_file() && e.path().filename().string()[0] != '.') out.push_back(e.path());
    } else if (std::filesystem::is_regular_file(p)) {
      out.emplace_back(p);
    } else {
      std::fprintf(stderr, "fuzz_replay: no such file or folder: %s\n", p.c_str());
      std::exit(2);
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  const std::map<std::string, Target> targets = {
#define CTB_ENTRY(name) {#name, &CtbFuzz_##name},
      CTB_FUZZ_TARGETS(CTB_ENTRY)
#undef CTB_ENTRY
  };
  if (argc < 3 || !targets.count(argv[1])) {
    std::fprintf(stderr, "usage: fuzz_replay TARGET PATH...\ntargets:");
    for (const auto& [name, fn] : targets) std::fprintf(stderr, " %s", name.c_str());
    std::fprintf(stderr, "\n");
    return 2;
  }
  const Target fn = targets.at(argv[1]);
  const auto inputs = Inputs(std::vector<std::string>(argv + 2, argv + argc));
  if (inputs.empty()) {
    std::fprintf(stderr, "fuzz_replay: no inputs\n");
    return 2;
  }
  int slow = 0;
  double slowest = 0;
  std::string slowest_name;
  for (const auto& path : inputs) {
    std::ifstream in(path, std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::fprintf(stderr, "replaying %s\n", path.c_str());
    const auto t0 = std::chrono::steady_clock::now();
    fn(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (s > slowest) slowest = s, slowest_name = path.string();
    if (s > kMaxSeconds) {
      std::fprintf(stderr, "SLOW %s: %.3f s (limit %.1f s)\n", path.c_str(), s, kMaxSeconds);
      ++slow;
    }
  }
  std::printf("%s: %zu inputs replayed, slowest %.3f s (%s)\n", argv[1], inputs.size(), slowest,
              slowest_name.c_str());
  return slow == 0 ? 0 : 1;
}

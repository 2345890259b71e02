// Writes a SolveRequest as wire bytes, for the seeds of the grpc_convert fuzz target (built on
// demand: `cmake --build build --target fuzz_grpc_seeds`).
//
//   fuzz_grpc_seeds OUT (--domain NAME | --action-model FILE) [--state-plan FILE] [--options JSON]
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "grpc/convert.h"

namespace {

ctb::Json ReadJson(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ctb::Json::parse(ss.str());
}

void Into(const ctb::Json& j, google::protobuf::Message* m) {
  if (auto err = ctb::grpcfront::FromJson(j, m)) {
    std::fprintf(stderr, "%s\n", err->c_str());
    std::exit(1);
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: fuzz_grpc_seeds OUT (--domain NAME | --action-model FILE) "
                         "[--state-plan FILE] [--options JSON]\n");
    return 2;
  }
  ::ctburton::v1::SolveRequest q;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string flag = argv[i], value = argv[i + 1];
    if (flag == "--domain") q.set_domain(value);
    else if (flag == "--action-model") Into(ReadJson(value), q.mutable_action_model());
    else if (flag == "--state-plan") Into(ReadJson(value), q.mutable_state_plan());
    else if (flag == "--options") Into(ctb::Json::parse(value), q.mutable_options());
    else return 2;
  }
  std::ofstream out(argv[1], std::ios::binary);
  out << q.SerializeAsString();
  return out ? 0 : 1;
}

// Conversions between the core's types and the gRPC messages (contract section 10). Documents
// follow protobuf's JSON mapping with the JSON keys as field names, converted in memory by
// reflection (grpc/proto_json.h: no JSON text is written and parsed back); statuses and errors
// are mapped by hand. Internal to grpc/.
#pragma once

#include <grpcpp/grpcpp.h>

#include <string>
#include <variant>

#include "app/core.h"
#include "ctburton/v1/planner.pb.h"

namespace ctb::grpcfront {

namespace pb = ::ctburton::v1;

// A message as the contract's JSON (field names as written in the .proto, unset fields left
// out). A google.protobuf.Value without a kind is written as {} (which no document accepts where
// a Value sits), never left out of its list.
Json ToJson(const google::protobuf::Message& m);
// JSON into a message; unknown keys are ignored (the core checks documents strictly itself).
// An error text when the JSON does not fit the message's types.
std::optional<std::string> FromJson(const Json& j, google::protobuf::Message* m);

app::RequestOptions OptionsOf(const pb::Options& o);

// The unified-planning status of an answer (section 10).
pb::PlanStatus StatusOf(const app::Answer& a);
// The whole result of a solve; `intermediate` marks an improving plan in a stream.
pb::PlanResult ResultOf(const app::Answer& a);
// An improving plan from the core's observer: its objective and bound, and the numbers of its
// `solution` event as metrics.
pb::PlanResult IntermediateOf(const SolveProgress& progress);

// An Error as a gRPC status: the code's mapping, every detail's "pointer: message" in the text,
// and a google.rpc.BadRequest with a field violation per detail.
grpc::Status StatusOf(const Error& e);

}  // namespace ctb::grpcfront

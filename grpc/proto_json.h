// Protobuf messages and the contract's JSON, converted in memory by reflection (no text in
// between). The mapping is protobuf's proto3 JSON mapping as the gRPC front end uses it: field
// names as written in the .proto (json names accepted on the way in), fields left out when unset
// (proto3 scalars at their default), 64-bit integers as strings, enums by name, NaN and the
// infinities as "NaN"/"Infinity"/"-Infinity", maps as objects, google.protobuf.Struct, Value and
// ListValue as the JSON they hold. Unknown fields are ignored both ways. Internal to grpc/.
#pragma once

#include <google/protobuf/message.h>

#include <optional>
#include <string>

#include "planner/model/json_io.h"

namespace ctb::grpcfront {

// A google.protobuf.Value without a kind is written as {} (which no document accepts where a
// Value sits), never left out of its list.
Json MessageToJsonValue(const google::protobuf::Message& m);

// Fills m (cleared first) from j; an error text naming the field when a value does not fit its
// field's type.
std::optional<std::string> JsonValueToMessage(const Json& j, google::protobuf::Message* m);

}  // namespace ctb::grpcfront

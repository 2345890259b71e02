#include "grpc/proto_json.h"

#include <google/protobuf/descriptor.h>
#include <google/protobuf/struct.pb.h>

#include <cmath>
#include <limits>

namespace ctb::grpcfront {

namespace {

using google::protobuf::Descriptor;
using google::protobuf::FieldDescriptor;
using google::protobuf::ListValue;
using google::protobuf::Message;
using google::protobuf::Reflection;
using google::protobuf::Struct;
using google::protobuf::Value;

// ---- message -> JSON ----

// As protobuf's printer writes a double (shortest form, %.15g first) and a JSON reader reads it
// back: a whole number below 10^15 is an integer (a template parameter N: 2 stays 2, not 2.0).
Json Number(double d) {
  if (std::isnan(d)) return "NaN";
  if (std::isinf(d)) return d > 0 ? "Infinity" : "-Infinity";
  if (std::floor(d) == d && std::fabs(d) < 1e15) return static_cast<long long>(d);
  return d;
}

Json ValueJson(const Value& v);

Json StructJson(const Struct& s) {
  Json out = Json::object();
  for (const auto& [k, v] : s.fields()) out[k] = ValueJson(v);
  return out;
}

Json ListJson(const ListValue& l) {
  Json out = Json::array();
  for (const auto& v : l.values()) out.push_back(ValueJson(v));
  return out;
}

Json ValueJson(const Value& v) {
  switch (v.kind_case()) {
    case Value::kNullValue: return nullptr;
    case Value::kNumberValue: return Number(v.number_value());
    case Value::kStringValue: return v.string_value();
    case Value::kBoolValue: return v.bool_value();
    case Value::kStructValue: return StructJson(v.struct_value());
    case Value::kListValue: return ListJson(v.list_value());
    case Value::KIND_NOT_SET: break;
  }
  return Json::object();  // no kind: {} at its place, which every loader refuses there
}

// Field f of m: element i of a repeated field, or the singular value (i < 0).
Json FieldJson(const Message& m, const FieldDescriptor* f, int i) {
  const Reflection* r = m.GetReflection();
  const bool rep = i >= 0;
  switch (f->cpp_type()) {
    case FieldDescriptor::CPPTYPE_INT32: return rep ? r->GetRepeatedInt32(m, f, i) : r->GetInt32(m, f);
    case FieldDescriptor::CPPTYPE_UINT32: return rep ? r->GetRepeatedUInt32(m, f, i) : r->GetUInt32(m, f);
    case FieldDescriptor::CPPTYPE_INT64:  // proto3 JSON: 64-bit integers as strings
      return std::to_string(rep ? r->GetRepeatedInt64(m, f, i) : r->GetInt64(m, f));
    case FieldDescriptor::CPPTYPE_UINT64:
      return std::to_string(rep ? r->GetRepeatedUInt64(m, f, i) : r->GetUInt64(m, f));
    case FieldDescriptor::CPPTYPE_DOUBLE: return Number(rep ? r->GetRepeatedDouble(m, f, i) : r->GetDouble(m, f));
    case FieldDescriptor::CPPTYPE_FLOAT: return Number(rep ? r->GetRepeatedFloat(m, f, i) : r->GetFloat(m, f));
    case FieldDescriptor::CPPTYPE_BOOL: return rep ? r->GetRepeatedBool(m, f, i) : r->GetBool(m, f);
    case FieldDescriptor::CPPTYPE_ENUM: {
      const int n = rep ? r->GetRepeatedEnumValue(m, f, i) : r->GetEnumValue(m, f);
      if (const auto* e = f->enum_type()->FindValueByNumber(n)) return e->name();
      return n;  // a number the .proto does not name (proto3 enums are open)
    }
    case FieldDescriptor::CPPTYPE_STRING: return rep ? r->GetRepeatedString(m, f, i) : r->GetString(m, f);
    case FieldDescriptor::CPPTYPE_MESSAGE:
      return MessageToJsonValue(rep ? r->GetRepeatedMessage(m, f, i) : r->GetMessage(m, f));
  }
  return nullptr;
}

// A map field: its entries' keys as text.
Json MapJson(const Message& m, const FieldDescriptor* f) {
  Json out = Json::object();
  const Reflection* r = m.GetReflection();
  for (int i = 0; i < r->FieldSize(m, f); ++i) {
    const Message& entry = r->GetRepeatedMessage(m, f, i);
    const Json key = FieldJson(entry, f->message_type()->map_key(), -1);
    const std::string text = key.is_string() ? key.get<std::string>() : key.dump();
    out[text] = FieldJson(entry, f->message_type()->map_value(), -1);
  }
  return out;
}

// ---- JSON -> message ----

std::optional<std::string> Fill(const Json& j, Message* m);

std::optional<long long> Integer(const Json& v) {
  if (v.is_number_integer()) return v.get<long long>();
  if (v.is_number_unsigned()) return std::nullopt;  // beyond long long
  if (v.is_number_float()) {
    const double d = v.get<double>();
    if (std::isfinite(d) && std::floor(d) == d && std::fabs(d) < 9.2e18) return static_cast<long long>(d);
    return std::nullopt;
  }
  if (v.is_string()) {
    const std::string& s = v.get_ref<const std::string&>();
    try {
      std::size_t used = 0;
      const long long n = std::stoll(s, &used);
      if (used == s.size()) return n;
    } catch (const std::exception&) {
    }
  }
  return std::nullopt;
}

std::optional<double> Real(const Json& v) {
  if (v.is_number()) return v.get<double>();
  if (!v.is_string()) return std::nullopt;
  const std::string& s = v.get_ref<const std::string&>();
  if (s == "NaN") return std::numeric_limits<double>::quiet_NaN();
  if (s == "Infinity") return std::numeric_limits<double>::infinity();
  if (s == "-Infinity") return -std::numeric_limits<double>::infinity();
  try {
    std::size_t used = 0;
    const double d = std::stod(s, &used);
    if (used == s.size()) return d;
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

void FillValue(const Json& j, Value* v);

void FillStruct(const Json& j, Struct* s) {
  for (const auto& [k, x] : j.items()) FillValue(x, &(*s->mutable_fields())[k]);
}

void FillList(const Json& j, ListValue* l) {
  for (const auto& x : j) FillValue(x, l->add_values());
}

void FillValue(const Json& j, Value* v) {
  if (j.is_null()) v->set_null_value(google::protobuf::NULL_VALUE);
  else if (j.is_boolean()) v->set_bool_value(j.get<bool>());
  else if (j.is_number()) v->set_number_value(j.get<double>());
  else if (j.is_string()) v->set_string_value(j.get<std::string>());
  else if (j.is_object()) FillStruct(j, v->mutable_struct_value());
  else FillList(j, v->mutable_list_value());
}

// Sets field f of m (one more element when repeated) from v.
std::optional<std::string> SetField(const Json& v, Message* m, const FieldDescriptor* f) {
  const Reflection* r = m->GetReflection();
  const bool rep = f->is_repeated();
  const std::string bad = "field " + f->name() + ": " + WireText(v).substr(0, 64) + " is not ";
  auto integer = [&](long long lo, long long hi) -> std::optional<long long> {
    auto n = Integer(v);
    return n && *n >= lo && *n <= hi ? n : std::nullopt;
  };
  switch (f->cpp_type()) {
    case FieldDescriptor::CPPTYPE_INT32: {
      auto n = integer(std::numeric_limits<int>::min(), std::numeric_limits<int>::max());
      if (!n) return bad + "a 32-bit integer";
      rep ? r->AddInt32(m, f, static_cast<int>(*n)) : r->SetInt32(m, f, static_cast<int>(*n));
      return std::nullopt;
    }
    case FieldDescriptor::CPPTYPE_UINT32: {
      auto n = integer(0, std::numeric_limits<unsigned>::max());
      if (!n) return bad + "an unsigned 32-bit integer";
      rep ? r->AddUInt32(m, f, static_cast<unsigned>(*n)) : r->SetUInt32(m, f, static_cast<unsigned>(*n));
      return std::nullopt;
    }
    case FieldDescriptor::CPPTYPE_INT64: {
      auto n = Integer(v);
      if (!n) return bad + "a 64-bit integer";
      rep ? r->AddInt64(m, f, *n) : r->SetInt64(m, f, *n);
      return std::nullopt;
    }
    case FieldDescriptor::CPPTYPE_UINT64: {
      auto n = integer(0, std::numeric_limits<long long>::max());
      if (!n) return bad + "an unsigned 64-bit integer";
      rep ? r->AddUInt64(m, f, static_cast<unsigned long long>(*n)) : r->SetUInt64(m, f, static_cast<unsigned long long>(*n));
      return std::nullopt;
    }
    case FieldDescriptor::CPPTYPE_DOUBLE:
    case FieldDescriptor::CPPTYPE_FLOAT: {
      auto d = Real(v);
      if (!d) return bad + "a number";
      if (f->cpp_type() == FieldDescriptor::CPPTYPE_FLOAT)
        rep ? r->AddFloat(m, f, static_cast<float>(*d)) : r->SetFloat(m, f, static_cast<float>(*d));
      else
        rep ? r->AddDouble(m, f, *d) : r->SetDouble(m, f, *d);
      return std::nullopt;
    }
    case FieldDescriptor::CPPTYPE_BOOL:
      if (!v.is_boolean()) return bad + "true or false";
      rep ? r->AddBool(m, f, v.get<bool>()) : r->SetBool(m, f, v.get<bool>());
      return std::nullopt;
    case FieldDescriptor::CPPTYPE_ENUM: {
      int n = 0;
      if (v.is_string()) {
        const auto* e = f->enum_type()->FindValueByName(v.get<std::string>());
        if (!e) return bad + "a value of " + f->enum_type()->name();
        n = e->number();
      } else if (auto k = integer(std::numeric_limits<int>::min(), std::numeric_limits<int>::max())) {
        n = static_cast<int>(*k);
      } else {
        return bad + "a value of " + f->enum_type()->name();
      }
      rep ? r->AddEnumValue(m, f, n) : r->SetEnumValue(m, f, n);
      return std::nullopt;
    }
    case FieldDescriptor::CPPTYPE_STRING:
      if (!v.is_string() || f->type() == FieldDescriptor::TYPE_BYTES) return bad + "a string";
      rep ? r->AddString(m, f, v.get<std::string>()) : r->SetString(m, f, v.get<std::string>());
      return std::nullopt;
    case FieldDescriptor::CPPTYPE_MESSAGE:
      return Fill(v, rep ? r->AddMessage(m, f) : r->MutableMessage(m, f));
  }
  return bad + "supported";
}

std::optional<std::string> SetMap(const Json& v, Message* m, const FieldDescriptor* f) {
  if (!v.is_object()) return "field " + f->name() + ": not an object";
  for (const auto& [k, x] : v.items()) {
    Message* entry = m->GetReflection()->AddMessage(m, f);
    if (auto e = SetField(Json(k), entry, f->message_type()->map_key())) return e;
    if (auto e = SetField(x, entry, f->message_type()->map_value())) return e;
  }
  return std::nullopt;
}

std::optional<std::string> SetMember(const Json& v, Message* m, const FieldDescriptor* f) {
  const bool value_typed = f->message_type() && f->message_type() == Value::descriptor();
  if (v.is_null() && !value_typed) return std::nullopt;  // null: the field stays unset
  if (f->is_map()) return SetMap(v, m, f);
  if (!f->is_repeated()) return SetField(v, m, f);
  if (!v.is_array()) return "field " + f->name() + ": not a list";
  for (const auto& x : v)
    if (auto e = SetField(x, m, f)) return e;
  return std::nullopt;
}

std::optional<std::string> Fill(const Json& j, Message* m) {
  const Descriptor* d = m->GetDescriptor();
  if (d == Value::descriptor()) {
    FillValue(j, static_cast<Value*>(m));
    return std::nullopt;
  }
  if (d == ListValue::descriptor()) {
    if (!j.is_array()) return d->name() + ": not a list";
    FillList(j, static_cast<ListValue*>(m));
    return std::nullopt;
  }
  if (!j.is_object()) return d->name() + ": not an object";
  if (d == Struct::descriptor()) {
    FillStruct(j, static_cast<Struct*>(m));
    return std::nullopt;
  }
  for (const auto& [k, v] : j.items()) {
    const FieldDescriptor* f = d->FindFieldByName(k);
    if (!f) f = d->FindFieldByCamelcaseName(k);
    if (!f) continue;  // unknown keys are ignored
    if (auto e = SetMember(v, m, f)) return e;
  }
  return std::nullopt;
}

}  // namespace

Json MessageToJsonValue(const Message& m) {
  const Descriptor* d = m.GetDescriptor();
  if (d == Value::descriptor()) return ValueJson(static_cast<const Value&>(m));
  if (d == Struct::descriptor()) return StructJson(static_cast<const Struct&>(m));
  if (d == ListValue::descriptor()) return ListJson(static_cast<const ListValue&>(m));
  Json out = Json::object();
  std::vector<const FieldDescriptor*> fields;
  m.GetReflection()->ListFields(m, &fields);  // set fields only, as proto3's mapping prints them
  for (const FieldDescriptor* f : fields) {
    if (f->is_map()) {
      out[f->name()] = MapJson(m, f);
    } else if (f->is_repeated()) {
      Json list = Json::array();
      for (int i = 0; i < m.GetReflection()->FieldSize(m, f); ++i) list.push_back(FieldJson(m, f, i));
      out[f->name()] = std::move(list);
    } else {
      out[f->name()] = FieldJson(m, f, -1);
    }
  }
  return out;
}

std::optional<std::string> JsonValueToMessage(const Json& j, Message* m) {
  m->Clear();
  return Fill(j, m);
}

}  // namespace ctb::grpcfront

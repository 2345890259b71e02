// --mqtt-url: what is accepted, and what each refusal says (mqtt/url.h).
#include "mqtt/url.h"

#include <gtest/gtest.h>

namespace ctb::mqtt {
namespace {

BrokerAddress Ok(const std::string& url) {
  auto r = ParseMqttUrl(url);
  EXPECT_TRUE(std::holds_alternative<BrokerAddress>(r)) << url << ": " << std::get<std::string>(r);
  return std::holds_alternative<BrokerAddress>(r) ? std::get<BrokerAddress>(r) : BrokerAddress{};
}

std::string Refused(const std::string& url) {
  auto r = ParseMqttUrl(url);
  EXPECT_TRUE(std::holds_alternative<std::string>(r)) << url << " was accepted";
  return std::holds_alternative<std::string>(r) ? std::get<std::string>(r) : "";
}

TEST(MqttUrl, HostPortAndDefaults) {
  auto a = Ok("mqtt://127.0.0.1:1884");
  EXPECT_EQ(a.host, "127.0.0.1");
  EXPECT_EQ(a.port, 1884);
  a = Ok("mqtt://broker.local");
  EXPECT_EQ(a.host, "broker.local");
  EXPECT_EQ(a.port, 1883);
  a = Ok("mqtt://[::1]:1885/");
  EXPECT_EQ(a.host, "::1");
  EXPECT_EQ(a.port, 1885);
}

TEST(MqttUrl, RefusalsSayWhy) {
  EXPECT_NE(Refused("http://127.0.0.1:1883").find("the scheme must be mqtt://"), std::string::npos);
  EXPECT_NE(Refused("mqtts://h").find("TLS"), std::string::npos);
  EXPECT_NE(Refused("mqtt://").find("no host"), std::string::npos);
  EXPECT_NE(Refused("mqtt://h:0").find("1..65535"), std::string::npos);
  EXPECT_NE(Refused("mqtt://h:65536").find("1..65535"), std::string::npos);
  EXPECT_NE(Refused("mqtt://h:12a").find("a number"), std::string::npos);
  EXPECT_NE(Refused("mqtt://h:").find("empty port"), std::string::npos);
  EXPECT_NE(Refused("mqtt://h/topic").find("path"), std::string::npos);
  EXPECT_NE(Refused("mqtt://::1:1883").find("brackets"), std::string::npos);
  EXPECT_NE(Refused("mqtt://h h").find("space"), std::string::npos);
  // Every refusal shows the expected form; a password is never echoed.
  EXPECT_NE(Refused("mqtt://h:0").find("expected mqtt://host[:port]"), std::string::npos);
  const std::string creds = Refused("mqtt://user:secret@h:1883");
  EXPECT_NE(creds.find("credentials are not supported"), std::string::npos);
  EXPECT_EQ(creds.find("secret"), std::string::npos) << creds;
}

}  // namespace
}  // namespace ctb::mqtt

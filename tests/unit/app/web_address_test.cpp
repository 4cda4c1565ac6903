#include "app/config/web_address.hpp"

#include <catch2/catch.hpp>
#include <stdexcept>

using dxlemu::app::parse_web_address;

TEST_CASE("The web address may be a port alone and serves loopback", "[web_address]") {
  const auto a = parse_web_address("8080");
  CHECK(a.address == "127.0.0.1");
  CHECK(a.port == 8080);
  CHECK(a.loopback());
  CHECK(parse_web_address("0").port == 0);
}

TEST_CASE("The web address may have an address before the port", "[web_address]") {
  const auto any = parse_web_address("0.0.0.0:9000");
  CHECK(any.address == "0.0.0.0");
  CHECK(any.port == 9000);
  CHECK_FALSE(any.loopback());
  CHECK(parse_web_address("localhost:80").address == "127.0.0.1");
  CHECK(parse_web_address("127.0.0.2:80").loopback());
  CHECK_FALSE(parse_web_address("192.168.1.5:80").loopback());
  const auto v6 = parse_web_address("[::1]:8080");
  CHECK(v6.address == "::1");
  CHECK(v6.loopback());
  CHECK_FALSE(parse_web_address("[::]:8080").loopback());
}

TEST_CASE("A web address that is not an address and a port is refused", "[web_address]") {
  using Catch::Matchers::Contains;
  CHECK_THROWS_WITH(parse_web_address(""), Contains("port must be a number from 0 to 65535"));
  CHECK_THROWS_WITH(parse_web_address("65536"), Contains("not \"65536\""));
  CHECK_THROWS_WITH(parse_web_address("80x"), Contains("not \"80x\""));
  CHECK_THROWS_WITH(parse_web_address("-1"), Contains("not \"-1\""));
  CHECK_THROWS_WITH(parse_web_address("example.com:80"),
                    Contains("\"example.com\" is not a numeric address"));
  CHECK_THROWS_WITH(parse_web_address("[1.2.3.4]:80"), Contains("is not an IPv6 address"));
  CHECK_THROWS_WITH(parse_web_address("::1:80"), Contains("is not a numeric address"));
  CHECK_THROWS_WITH(parse_web_address("1.2.3.4:"), Contains("not \"\""));
}

// The control protocol: every command round-trips; malformed, hostile and oversized lines are
// refused.
#include "slicecap/control/protocol.hpp"

#include <gtest/gtest.h>

#include <random>

namespace slicecap::control {
namespace {

ProtocolError refusal(std::string_view line) {
  auto parsed = parseRequest(line);
  EXPECT_TRUE(std::holds_alternative<ProtocolError>(parsed)) << line;
  return std::holds_alternative<ProtocolError>(parsed) ? std::get<ProtocolError>(parsed)
                                                       : ProtocolError{};
}

Request accepted(std::string_view line) {
  auto parsed = parseRequest(line);
  EXPECT_TRUE(std::holds_alternative<Request>(parsed))
      << line << ": "
      << (std::holds_alternative<ProtocolError>(parsed) ? std::get<ProtocolError>(parsed).message
                                                        : "");
  return std::holds_alternative<Request>(parsed) ? std::get<Request>(parsed) : Request{};
}

TEST(Protocol, EveryCommandRoundTrips) {
  const SliceId slice{SliceKind::Axial, {30, 75}};
  const std::vector<Command> commands{Hello{},
                                      SessionNew{"red felt, warp along x", std::string("felt-1")},
                                      SessionNew{"leather", std::nullopt},
                                      SessionList{},
                                      SessionShow{"felt-1"},
                                      SessionResume{"felt-1"},
                                      SessionDelete{"felt-1"},
                                      SweepStart{slice},
                                      SweepStop{},
                                      SweepRedo{{SliceKind::Diagonal, {75, 75}}},
                                      Status{},
                                      Reconstruct{std::string("felt-1"), "b"},
                                      Export{std::nullopt, "/var/lib/slicecap/out", std::nullopt},
                                      Export{std::string("felt-1"), "", std::string("prior")}};
  std::int64_t id = 1;
  for (const Command& command : commands) {
    const std::string line = encodeRequest({id, command});
    EXPECT_EQ(line.find('\n'), std::string::npos);
    const Request back = accepted(line);
    EXPECT_EQ(back.id, id);
    EXPECT_EQ(back.command.index(), command.index()) << line;
    EXPECT_EQ(encodeRequest(back), line) << "a request survives a round trip unchanged";
    ++id;
  }
  const Request start = accepted(encodeRequest({9, SweepStart{slice}}));
  EXPECT_EQ(std::get<SweepStart>(start.command).slice, slice);
}

TEST(Protocol, RefusesMalformedLinesWithTheRightCode) {
  EXPECT_EQ(refusal("").code, ErrorCode::ParseError);
  EXPECT_EQ(refusal("status").code, ErrorCode::ParseError);
  EXPECT_EQ(refusal("[1,2]").code, ErrorCode::ParseError);
  EXPECT_EQ(refusal("{\"v\":1,\"id\":3,\"cmd\":\"status\"").code, ErrorCode::ParseError)
      << "truncated";
  EXPECT_EQ(refusal("{\"v\":1,\"cmd\":\"status\"}").code, ErrorCode::BadRequest) << "no id";
  EXPECT_EQ(refusal("{\"id\":3,\"cmd\":\"status\"}").code, ErrorCode::BadRequest) << "no version";
  const ProtocolError v2 = refusal("{\"v\":2,\"id\":3,\"cmd\":\"status\"}");
  EXPECT_EQ(v2.code, ErrorCode::UnsupportedVersion);
  EXPECT_EQ(v2.requestId, 3) << "the id is echoed whenever it could be read";
  EXPECT_EQ(refusal("{\"v\":1,\"id\":3,\"cmd\":\"reboot\"}").message, "unknown command \"reboot\"");
  EXPECT_EQ(refusal("{\"v\":1,\"id\":3,\"cmd\":7}").code, ErrorCode::BadRequest);
  EXPECT_EQ(refusal("{\"v\":1,\"id\":3,\"cmd\":\"status\",\"args\":[]}").code,
            ErrorCode::BadRequest);
}

TEST(Protocol, ValidatesArgumentsAndNamesTheField) {
  const auto start = [](const std::string& args) {
    return refusal("{\"v\":1,\"id\":1,\"cmd\":\"sweep.start\",\"args\":" + args + "}").message;
  };
  EXPECT_NE(start("{}").find("\"kind\""), std::string::npos);
  EXPECT_NE(start("{\"kind\":\"radial\",\"theta_i\":30,\"theta_v\":30}").find("axial"),
            std::string::npos);
  // Point slices exist in the offline formats, but no sweep makes one.
  const ProtocolError point = refusal(
      "{\"v\":1,\"id\":1,\"cmd\":\"sweep.start\",\"args\":{\"kind\":\"point\",\"theta_i\":30,"
      "\"theta_v\":30}}");
  EXPECT_EQ(point.code, ErrorCode::BadRequest);
  EXPECT_NE(point.message.find("\"axial\" or \"diagonal\""), std::string::npos) << point.message;
  EXPECT_NE(start("{\"kind\":\"axial\",\"theta_i\":45,\"theta_v\":30}")
                .find("\"theta_i\" must be 30 or 75"),
            std::string::npos);
  EXPECT_NE(start("{\"kind\":\"axial\",\"theta_i\":30,\"theta_v\":\"75\"}")
                .find("\"theta_v\" must be a number"),
            std::string::npos);
  // Session ids name directories: no path tricks.
  // Nor a leading '-' or '_': the CLI would read "-x" as an option, also in a pasted hint.
  for (const char* id : {"../etc", "a/b", "", "UPPER", "with space", ".hidden", "-x", "--", "_a"}) {
    const std::string line =
        std::string("{\"v\":1,\"id\":1,\"cmd\":\"session.show\",\"args\":{\"id\":\"") + id + "\"}}";
    EXPECT_EQ(refusal(line).code, ErrorCode::BadRequest) << id;
  }
  // A method name becomes part of a file name in the session's folder.
  for (const char* method : {"../../etc/x", "b/c", "", "B", "prior.exr"}) {
    for (const char* command : {"export", "reconstruct"}) {
      const std::string line = std::string("{\"v\":1,\"id\":1,\"cmd\":\"") + command +
                               "\",\"args\":{\"method\":\"" + method + "\"}}";
      EXPECT_EQ(refusal(line).code, ErrorCode::BadRequest) << line;
    }
  }
  const Request exportPrior =
      accepted("{\"v\":1,\"id\":1,\"cmd\":\"export\",\"args\":{\"method\":\"a-gamma\"}}");
  EXPECT_EQ(std::get<Export>(exportPrior.command).method, "a-gamma");
  EXPECT_NE(refusal("{\"v\":1,\"id\":1,\"cmd\":\"export\",\"args\":{\"directory\":\"out\"}}")
                .message.find("absolute"),
            std::string::npos);
  EXPECT_NE(refusal("{\"v\":1,\"id\":1,\"cmd\":\"session.new\",\"args\":{\"material\":\"" +
                    std::string(300, 'x') + "\"}}")
                .message.find("1 to 256 bytes"),
            std::string::npos);
  // A material name is printed on an operator's terminal: no forged lines, no escape sequences.
  for (const char* material : {"red\\nfoo", "red\\u001b[2J", "tab\\there", "del\\u007f"}) {
    EXPECT_NE(refusal("{\"v\":1,\"id\":1,\"cmd\":\"session.new\",\"args\":{\"material\":\"" +
                      std::string(material) + "\"}}")
                  .message.find("must not contain control characters"),
              std::string::npos)
        << material;
  }
  EXPECT_EQ(std::get<SessionNew>(
                accepted("{\"v\":1,\"id\":1,\"cmd\":\"session.new\",\"args\":{\"material\":"
                         "\"rotes Leder \u00e4\"}}")
                    .command)
                .material,
            "rotes Leder \u00e4");
}

TEST(Protocol, RefusesC1ControlsAndBidiOverridesInNames) {
  // `session list` prints the name raw: U+009B is a CSI on many terminals, and U+202E (and the
  // other embeddings, overrides and isolates) reverses what the operator reads after it.
  for (const char* character :
       {"\\u0080", "\\u009b", "\\u009f", "\\u202a", "\\u202e", "\\u2066", "\\u2069"}) {
    for (const char* argument : {"material", "directory"}) {
      const std::string command = std::string(argument) == "material" ? "session.new" : "export";
      const std::string line = "{\"v\":1,\"id\":1,\"cmd\":\"" + command + "\",\"args\":{\"" +
                               argument + "\":\"/red " + character + "felt\"}}";
      const ProtocolError error = refusal(line);
      EXPECT_EQ(error.code, ErrorCode::BadRequest) << line;
      EXPECT_NE(error.message.find(std::string("\"") + argument + "\" must not contain"),
                std::string::npos)
          << error.message;
    }
  }
  // Their neighbours are ordinary text.
  for (const char* character : {"\\u00a0", "\\u00e4", "\\u2030", "\\u202f", "\\u2065", "\\u206a"})
    accepted("{\"v\":1,\"id\":1,\"cmd\":\"session.new\",\"args\":{\"material\":\"red " +
             std::string(character) + "\"}}");
}

TEST(Protocol, SurvivesHostileInput) {
  EXPECT_EQ(refusal(std::string(kMaxRequestBytes + 1, '{')).code, ErrorCode::TooLarge);
  // Deep nesting within the size limit must not overflow the stack.
  const std::string deep = std::string(30000, '[') + std::string(30000, ']');
  EXPECT_EQ(refusal(deep).code, ErrorCode::ParseError);
  const std::string deepArgs =
      "{\"v\":1,\"id\":1,\"cmd\":\"status\",\"args\":{\"x\":" + std::string(20000, '[') +
      std::string(20000, ']') + "}}";
  EXPECT_TRUE(std::holds_alternative<Request>(parseRequest(deepArgs)))
      << "unknown arguments are ignored";
  // Invalid UTF-8 and control bytes.
  EXPECT_EQ(refusal("{\"v\":1,\"id\":1,\"cmd\":\"\xff\xfe\"}").code, ErrorCode::ParseError);
  EXPECT_EQ(refusal(std::string("{\"v\":1,\0\"id\":1}", 14)).code, ErrorCode::ParseError);
  // 10 000 random lines: each gets an answer, none throws.
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> byte(0, 255), length(0, 200);
  const std::string seed = encodeRequest({4, SweepStart{{SliceKind::Diagonal, {30, 75}}}});
  for (int i = 0; i < 10000; ++i) {
    std::string line = seed;
    for (int k = length(rng) % 8; k > 0; --k)
      line[std::size_t(length(rng)) % line.size()] = char(byte(rng));
    if (i % 3 == 0) line.resize(std::size_t(length(rng)) % line.size());
    EXPECT_NO_THROW(parseRequest(line));
  }
}

TEST(Protocol, ResponsesAreOneLineAndNeverThrow) {
  const std::string ok = encodeResult(5, {{"material", std::string("caf\xc3\xa9 \xff")}});
  EXPECT_EQ(ok.find('\n'), std::string::npos);
  EXPECT_NE(ok.find("\"ok\":true"), std::string::npos);
  const std::string error = encodeError({ErrorCode::Conflict, "a sweep is already running", 5});
  const auto parsed = nlohmann::json::parse(error);
  EXPECT_EQ(parsed["error"]["code"], "conflict");
  EXPECT_EQ(parsed["id"], 5);
  EXPECT_TRUE(nlohmann::json::parse(encodeError({ErrorCode::ParseError, "x", std::nullopt}))["id"]
                  .is_null());
}

}  // namespace
}  // namespace slicecap::control

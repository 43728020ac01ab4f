// Connect tokens (issue, parse, verify, replay table), their text form, key
// files, and the Hello field that carries them.
#include "jetrace/auth/connect_token.hpp"
#include "jetrace/auth/key_file.hpp"
#include "jetrace/auth/token_verifier.hpp"
#include "jetrace/proto/messages.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <sys/stat.h>
#include <unistd.h>

namespace {

using namespace jetrace::auth;
namespace fs = std::filesystem;

constexpr std::int64_t kNow = 1'700'000'000;  // a fixed wall clock (unit: s since 1970)

struct Keys {
    KeyPair pair = generate_key_pair();
    KeyPair other = generate_key_pair();
};

TokenVerifier verifier(const PublicKey& key, std::size_t max_nonces = 16, std::string race = "") {
    return TokenVerifier(VerifierConfig{key, std::move(race), max_nonces});
}

/// A fresh directory under the system's temporary one, removed at the end.
struct TempDir {
    fs::path path = fs::temp_directory_path() / ("jetrace_auth_" + std::to_string(::getpid()) + "_" +
                                                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
    TempDir() {
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() { fs::remove_all(path); }
    std::string file(const char* name) const { return (path / name).string(); }
};

void write_text(const std::string& path, const std::string& text, mode_t mode) {
    std::ofstream(path, std::ios::trunc) << text;
    ::chmod(path.c_str(), mode);
}

}  // namespace

TEST(ConnectToken, IssuedTokenParsesAndVerifies) {
    Keys k;
    const auto bytes = issue_connect_token(k.pair.secret_key, "alice", kNow + 60, "cup-7");
    std::string error;
    const auto t = parse_connect_token(bytes, &error);
    ASSERT_TRUE(t) << error;
    EXPECT_EQ(t->name, "alice");
    EXPECT_EQ(t->expires_unix_s, kNow + 60);
    EXPECT_EQ(t->race_id, "cup-7");
    EXPECT_TRUE(signature_valid(*t, k.pair.public_key));
    EXPECT_FALSE(signature_valid(*t, k.other.public_key));
    EXPECT_EQ(serialize(*t), bytes);
    // Two tokens for the same player differ (random nonces).
    EXPECT_NE(issue_connect_token(k.pair.secret_key, "alice", kNow + 60, "cup-7"), bytes);
    EXPECT_EQ(public_key_of(k.pair.secret_key), k.pair.public_key);
}

TEST(ConnectToken, VerifierAdmitsOnceAndNamesEveryRefusal) {
    Keys k;
    auto v = verifier(k.pair.public_key);
    const auto good = issue_connect_token(k.pair.secret_key, "alice", kNow + 60);
    Verdict ok = v.check(good, "alice", kNow);
    ASSERT_TRUE(ok.ok()) << ok.refusal;
    v.admit(ok.token);
    EXPECT_EQ(v.check(good, "alice", kNow + 1).refusal, "connect token already used");
    EXPECT_EQ(v.check({}, "alice", kNow).refusal, "private race: a connect token is required");
    EXPECT_EQ(v.check(issue_connect_token(k.other.secret_key, "alice", kNow + 60), "alice", kNow).refusal,
              "connect token not signed with this server's key");
    EXPECT_EQ(v.check(issue_connect_token(k.pair.secret_key, "alice", kNow - 5), "alice", kNow).refusal,
              "connect token expired 5 s ago");
    EXPECT_TRUE(v.check(issue_connect_token(k.pair.secret_key, "alice", kNow), "alice", kNow).ok())
        << "valid up to and including its expiry second";
    EXPECT_EQ(v.check(issue_connect_token(k.pair.secret_key, "alice", kNow + 60), "mallory", kNow).refusal,
              "connect token was issued to 'alice', not to 'mallory'");
    EXPECT_EQ(v.check(issue_connect_token(k.pair.secret_key, "alice", kNow + 60, "other-race"), "alice", kNow).refusal,
              "connect token is for race 'other-race', this server hosts ''");
    const std::vector<std::uint8_t> junk(40, 7);
    EXPECT_EQ(v.check(junk, "alice", kNow).refusal, "connect token malformed: too short");
}

TEST(ConnectToken, RaceIdMustMatchTheServers) {
    Keys k;
    auto v = verifier(k.pair.public_key, 16, "cup-7");
    EXPECT_TRUE(v.check(issue_connect_token(k.pair.secret_key, "bob", kNow + 9, "cup-7"), "bob", kNow).ok());
    EXPECT_FALSE(v.check(issue_connect_token(k.pair.secret_key, "bob", kNow + 9), "bob", kNow).ok());
}

TEST(ConnectToken, ReplayTableIsBoundedAndForgetsExpiredNonces) {
    Keys k;
    auto v = verifier(k.pair.public_key, 2);
    for (int i = 0; i < 2; ++i) {
        const Verdict ok = v.check(issue_connect_token(k.pair.secret_key, "p", kNow + 10 + i), "p", kNow);
        ASSERT_TRUE(ok.ok()) << ok.refusal;
        v.admit(ok.token);
    }
    const auto third = issue_connect_token(k.pair.secret_key, "p", kNow + 100);
    EXPECT_EQ(v.check(third, "p", kNow).refusal, "too many connect tokens in use (2): try again when some have expired");
    EXPECT_EQ(v.nonces_held(), 2u);
    // Once the first has expired its nonce is forgotten and there is room.
    const Verdict later = v.check(third, "p", kNow + 11);
    EXPECT_TRUE(later.ok()) << later.refusal;
    EXPECT_EQ(v.nonces_held(), 1u);
}

TEST(ConnectToken, EveryTruncationIsRefused) {
    Keys k;
    const auto bytes = issue_connect_token(k.pair.secret_key, "alice", kNow + 60, "r");
    for (std::size_t n = 0; n < bytes.size(); ++n) {
        const std::span<const std::uint8_t> cut(bytes.data(), n);
        EXPECT_FALSE(parse_connect_token(cut)) << "a " << n << "-byte prefix parsed";
    }
    auto longer = bytes;
    longer.push_back(0);
    std::string error;
    EXPECT_FALSE(parse_connect_token(longer, &error));
    EXPECT_EQ(error, "trailing bytes after the signature");
}

TEST(ConnectToken, EveryTamperedByteIsRefused) {
    Keys k;
    auto v = verifier(k.pair.public_key);
    const auto bytes = issue_connect_token(k.pair.secret_key, "alice", kNow + 60, "r");
    for (std::size_t i = 0; i < bytes.size(); ++i) {
        for (const std::uint8_t flip : {std::uint8_t{0x01}, std::uint8_t{0x80}}) {
            auto bad = bytes;
            bad[i] ^= flip;
            EXPECT_FALSE(v.check(bad, "alice", kNow).ok()) << "byte " << i << " ^ " << int{flip} << " still admitted";
        }
    }
}

TEST(ConnectToken, ParserChecksTheLayout) {
    Keys k;
    ConnectToken t;
    t.name = "alice";
    t.expires_unix_s = kNow;
    sign(t, k.pair.secret_key);
    auto bytes = serialize(t);
    std::string error;
    auto bad = bytes;
    bad[0] = 2;
    EXPECT_FALSE(parse_connect_token(bad, &error));
    EXPECT_EQ(error, "unknown version");
    bad = bytes;
    bad[1] = 33;
    EXPECT_FALSE(parse_connect_token(bad, &error));
    EXPECT_EQ(error, "name too long");
    bad = bytes;
    bad[2] = 0x01;  // a control character in the name
    EXPECT_FALSE(parse_connect_token(bad, &error));
    EXPECT_EQ(error, "name is not UTF-8 text");
    bad = bytes;
    bad[2 + 5 + 7] = 0x80;  // expiry's top byte: above INT64_MAX
    EXPECT_FALSE(parse_connect_token(bad, &error));
    EXPECT_EQ(error, "expiry out of range");
    bad = bytes;
    bad[2 + 5 + 8 + 16] = 65;
    EXPECT_FALSE(parse_connect_token(bad, &error));
    EXPECT_EQ(error, "race id too long");
    EXPECT_FALSE(parse_connect_token(std::vector<std::uint8_t>(kMaxTokenBytes + 1, 1), &error));
    EXPECT_EQ(error, "too long");
}

TEST(ConnectToken, TextForm) {
    Keys k;
    const auto bytes = issue_connect_token(k.pair.secret_key, "alice", kNow + 60);
    const std::string text = to_text(bytes);
    EXPECT_EQ(text.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_"),
              std::string::npos);
    EXPECT_EQ(from_text("  " + text + "\n", kMaxTokenBytes), bytes);
    EXPECT_FALSE(from_text(text + "=", kMaxTokenBytes));
    EXPECT_FALSE(from_text(text + "!", kMaxTokenBytes));
    EXPECT_FALSE(from_text("", kMaxTokenBytes));
    EXPECT_FALSE(from_text(text, bytes.size() - 1)) << "longer than the caller allows";
}

TEST(KeyFile, WrittenKeysLoadBackAndSecretsMustBePrivate) {
    TempDir dir;
    const KeyPair keys = generate_key_pair();
    const std::string path = dir.file("race.key");
    std::string error;
    ASSERT_TRUE(write_key_files(path, keys, false, error)) << error;
    EXPECT_FALSE(write_key_files(path, keys, false, error));
    EXPECT_NE(error.find("exists already"), std::string::npos) << error;

    LoadedKey secret, pub;
    ASSERT_TRUE(load_key_file(path, secret, error)) << error;
    EXPECT_TRUE(secret.has_secret);
    EXPECT_EQ(secret.secret, keys.secret_key);
    EXPECT_EQ(secret.public_key, keys.public_key);
    ASSERT_TRUE(load_key_file(path + ".pub", pub, error)) << error;
    EXPECT_FALSE(pub.has_secret);
    EXPECT_EQ(pub.public_key, keys.public_key);

    ::chmod(path.c_str(), 0640);
    EXPECT_FALSE(load_key_file(path, secret, error));
    EXPECT_NE(error.find("permissions 0640 are too open"), std::string::npos) << error;
    ::chmod((path + ".pub").c_str(), 0666);
    EXPECT_TRUE(load_key_file(path + ".pub", pub, error)) << "a public key may be read by anyone";
}

TEST(KeyFile, BadFilesAreRefusedWithTheReason) {
    TempDir dir;
    LoadedKey key;
    std::string error;
    EXPECT_FALSE(load_key_file(dir.file("missing"), key, error));
    EXPECT_NE(error.find("No such file"), std::string::npos) << error;
    EXPECT_FALSE(load_key_file(dir.path.string(), key, error));
    EXPECT_NE(error.find("not a regular file"), std::string::npos) << error;
    write_text(dir.file("big"), std::string(2000, 'a'), 0600);
    EXPECT_FALSE(load_key_file(dir.file("big"), key, error));
    EXPECT_NE(error.find("larger than 1024 bytes"), std::string::npos) << error;
    write_text(dir.file("other"), "ssh-ed25519 AAAA\n", 0600);
    EXPECT_FALSE(load_key_file(dir.file("other"), key, error));
    EXPECT_NE(error.find("not a jetrace key file"), std::string::npos) << error;
    write_text(dir.file("short"), "jetrace-ed25519-public-key AAAA\n", 0600);
    EXPECT_FALSE(load_key_file(dir.file("short"), key, error));
    EXPECT_NE(error.find("not 32 bytes"), std::string::npos) << error;
    // A secret key whose public half belongs to another seed.
    const KeyPair a = generate_key_pair(), b = generate_key_pair();
    SecretKey mixed = a.secret_key;
    std::copy(b.public_key.begin(), b.public_key.end(), mixed.begin() + 32);
    write_text(dir.file("mixed"), "jetrace-ed25519-secret-key " + to_text(mixed) + "\n", 0600);
    EXPECT_FALSE(load_key_file(dir.file("mixed"), key, error));
    EXPECT_NE(error.find("corrupt secret key"), std::string::npos) << error;
}

TEST(HelloConnectToken, TravelsInHelloAndIsBounded) {
    jetrace::proto::Hello h;
    h.name = "alice";
    h.connect_token.assign(kMaxTokenBytes, 0xAB);
    jetrace::proto::Message m;
    std::string error;
    ASSERT_TRUE(jetrace::proto::decode(jetrace::proto::encode(h), m, error)) << error;
    EXPECT_EQ(std::get<jetrace::proto::Hello>(m).connect_token, h.connect_token);
    // A Hello without one (every older client) decodes with none.
    h.connect_token.clear();
    ASSERT_TRUE(jetrace::proto::decode(jetrace::proto::encode(h), m, error)) << error;
    EXPECT_TRUE(std::get<jetrace::proto::Hello>(m).connect_token.empty());
}

// DTLS 1.2 over memory BIOs: real OpenSSL handshakes between the server
// endpoint and an in-process client with its own certificate, datagram by
// datagram; the fingerprint check both ways; a lost flight retransmitted on
// the timer; garbage ignored; application records both ways; close_notify.
#include "jetrace/webrtc/dtls.hpp"

#include <gtest/gtest.h>
#include <openssl/evp.h>
#include <openssl/x509.h>

#include <thread>

using namespace jetrace::webrtc;

namespace {

using Bytes = std::vector<std::uint8_t>;

std::unique_ptr<DtlsContext> make_context(const DtlsSettings& s = {}) {
    std::string error;
    auto c = DtlsContext::create(s, &error);
    EXPECT_NE(c, nullptr) << error;
    return c;
}

// Moves datagrams between the two until neither has any; the largest seen.
std::size_t pump(DtlsEndpoint& a, DtlsEndpoint& b) {
    std::size_t largest = 0;
    for (int round = 0; round < 32; ++round) {
        auto from_a = a.take_outgoing();
        auto from_b = b.take_outgoing();
        if (from_a.empty() && from_b.empty()) break;
        for (const auto& d : from_a) {
            largest = std::max(largest, d.size());
            b.feed(d);
        }
        for (const auto& d : from_b) {
            largest = std::max(largest, d.size());
            a.feed(d);
        }
    }
    return largest;
}

// Like pump(), but each side's datagrams of one round are joined into one,
// as BoringSSL (Chromium) packs a handshake flight.
void pump_packed(DtlsEndpoint& a, DtlsEndpoint& b) {
    for (int round = 0; round < 32; ++round) {
        Bytes from_a, from_b;
        for (const auto& d : a.take_outgoing()) from_a.insert(from_a.end(), d.begin(), d.end());
        for (const auto& d : b.take_outgoing()) from_b.insert(from_b.end(), d.begin(), d.end());
        if (from_a.empty() && from_b.empty()) break;
        if (!from_a.empty()) b.feed(from_a);
        if (!from_b.empty()) a.feed(from_b);
    }
}

struct Peers {
    std::unique_ptr<DtlsContext> server_context = make_context();
    std::unique_ptr<DtlsContext> client_context = make_context();
};

Bytes text(std::string_view s) { return Bytes(s.begin(), s.end()); }

}  // namespace

TEST(Dtls, CertificateIsSelfSignedP256WithItsFingerprint) {
    DtlsSettings s;
    s.certificate_days = 30;
    const auto c = make_context(s);
    ASSERT_NE(c, nullptr);
    const Bytes& der = c->certificate_der();
    // The fingerprint is SHA-256 of the DER, computed here independently.
    Sha256Fingerprint digest{};
    unsigned int n = 0;
    ASSERT_EQ(EVP_Digest(der.data(), der.size(), digest.data(), &n, EVP_sha256(), nullptr), 1);
    EXPECT_EQ(digest, c->fingerprint());
    const unsigned char* p = der.data();
    X509* x = d2i_X509(nullptr, &p, static_cast<long>(der.size()));
    ASSERT_NE(x, nullptr);
    EVP_PKEY* key = X509_get0_pubkey(x);
    ASSERT_NE(key, nullptr);
    EXPECT_EQ(EVP_PKEY_get_base_id(key), EVP_PKEY_EC);
    char group[64] = {};
    std::size_t group_len = 0;
    ASSERT_EQ(EVP_PKEY_get_group_name(key, group, sizeof group, &group_len), 1);
    EXPECT_STREQ(group, "prime256v1");
    EXPECT_EQ(X509_verify(x, key), 1);  // signed by its own key
    int days = 0, seconds = 0;
    ASSERT_EQ(ASN1_TIME_diff(&days, &seconds, X509_get0_notBefore(x), X509_get0_notAfter(x)), 1);
    EXPECT_EQ(days, 30);
    EXPECT_EQ(seconds, 3600);
    X509_free(x);
    // A second context has another key, so another fingerprint.
    EXPECT_NE(make_context()->fingerprint(), c->fingerprint());
}

TEST(Dtls, HandshakeAndApplicationDataBothWays) {
    Peers p;
    DtlsEndpoint server(*p.server_context, DtlsRole::kServer, p.client_context->fingerprint());
    DtlsEndpoint client(*p.client_context, DtlsRole::kClient, p.server_context->fingerprint());
    EXPECT_FALSE(server.handshake_done());
    EXPECT_FALSE(client.send(text("too early")));
    const std::size_t largest = pump(client, server);
    ASSERT_TRUE(server.handshake_done()) << server.error_detail();
    ASSERT_TRUE(client.handshake_done()) << client.error_detail();
    EXPECT_LE(largest, 1200u);
    EXPECT_GT(largest, 0u);
    for (const auto& d : client.take_outgoing()) EXPECT_TRUE(is_dtls(d));
    ASSERT_TRUE(client.send(text("hello server")));
    ASSERT_TRUE(client.send(text("second record")));
    pump(client, server);
    const auto got = server.take_received();
    ASSERT_EQ(got.size(), 2u);
    EXPECT_EQ(got[0], text("hello server"));
    EXPECT_EQ(got[1], text("second record"));
    // A near-MTU SCTP packet goes in one record and one datagram.
    Bytes big(1100);
    for (std::size_t i = 0; i < big.size(); ++i) big[i] = static_cast<std::uint8_t>(i * 7);
    ASSERT_TRUE(server.send(big));
    const auto out = server.take_outgoing();
    ASSERT_EQ(out.size(), 1u);
    EXPECT_LE(out[0].size(), 1200u);
    client.feed(out[0]);
    const auto back = client.take_received();
    ASSERT_EQ(back.size(), 1u);
    EXPECT_EQ(back[0], big);
    EXPECT_FALSE(server.send(Bytes(1200)));  // cannot fit one datagram
    EXPECT_TRUE(server.handshake_done());
}

TEST(Dtls, DemultiplexesByFirstByte) {
    Peers p;
    DtlsEndpoint client(*p.client_context, DtlsRole::kClient, p.server_context->fingerprint());
    const auto hello = client.take_outgoing();
    ASSERT_FALSE(hello.empty());
    EXPECT_TRUE(is_dtls(hello[0]));  // 22: handshake
    EXPECT_FALSE(is_dtls(Bytes{0x00, 0x01}));  // STUN
    EXPECT_FALSE(is_dtls(Bytes{64}));
    EXPECT_FALSE(is_dtls(Bytes{19}));
    EXPECT_FALSE(is_dtls(Bytes{}));
}

TEST(Dtls, PackedFlightsAreRead) {
    Peers p;
    DtlsEndpoint server(*p.server_context, DtlsRole::kServer, p.client_context->fingerprint());
    DtlsEndpoint client(*p.client_context, DtlsRole::kClient, p.server_context->fingerprint());
    pump_packed(client, server);
    ASSERT_TRUE(server.handshake_done()) << server.error_detail();
    ASSERT_TRUE(client.handshake_done()) << client.error_detail();
    ASSERT_TRUE(client.send(text("one")));
    ASSERT_TRUE(client.send(text("two")));
    pump_packed(client, server);
    const auto got = server.take_received();
    ASSERT_EQ(got.size(), 2u);
    EXPECT_EQ(got[1], text("two"));
}

TEST(Dtls, ServerRefusesClientCertificateWithOtherFingerprint) {
    Peers p;
    Sha256Fingerprint wrong = p.client_context->fingerprint();
    wrong[31] ^= 1;
    DtlsEndpoint server(*p.server_context, DtlsRole::kServer, wrong);
    DtlsEndpoint client(*p.client_context, DtlsRole::kClient, p.server_context->fingerprint());
    pump(client, server);
    EXPECT_EQ(server.state(), DtlsState::kFailed);
    EXPECT_EQ(server.error(), DtlsError::kFingerprintMismatch);
    EXPECT_FALSE(server.error_detail().empty());
    EXPECT_FALSE(client.handshake_done());  // the alert reached it
    EXPECT_EQ(client.state(), DtlsState::kFailed);
    EXPECT_FALSE(server.send(text("x")));
}

TEST(Dtls, ClientRefusesServerCertificateWithOtherFingerprint) {
    Peers p;
    const auto impostor = make_context();
    DtlsEndpoint server(*impostor, DtlsRole::kServer, p.client_context->fingerprint());
    DtlsEndpoint client(*p.client_context, DtlsRole::kClient, p.server_context->fingerprint());
    pump(client, server);
    EXPECT_EQ(client.error(), DtlsError::kFingerprintMismatch);
    EXPECT_FALSE(server.handshake_done());
}

TEST(Dtls, LostFlightIsRetransmittedOnTheTimer) {
    DtlsSettings s;
    s.initial_retransmit_ms = 50;
    const auto sc = make_context(s);
    const auto cc = make_context(s);
    DtlsEndpoint server(*sc, DtlsRole::kServer, cc->fingerprint());
    DtlsEndpoint client(*cc, DtlsRole::kClient, sc->fingerprint());
    for (const auto& d : client.take_outgoing()) server.feed(d);
    const auto lost = server.take_outgoing();  // the server's first flight never arrives
    ASSERT_FALSE(lost.empty());
    const auto wait = server.next_timeout();
    ASSERT_TRUE(wait.has_value());
    EXPECT_LE(wait->count(), 50);
    server.handle_timeout();  // not yet expired: nothing is sent
    EXPECT_TRUE(server.take_outgoing().empty());
    std::this_thread::sleep_for(std::chrono::milliseconds(70));
    server.handle_timeout();
    const auto again = server.take_outgoing();
    ASSERT_EQ(again.size(), lost.size());
    for (const auto& d : again) client.feed(d);
    pump(client, server);
    EXPECT_TRUE(server.handshake_done()) << int(server.state()) << " " << server.error_detail();
    EXPECT_TRUE(client.handshake_done()) << int(client.state()) << " " << client.error_detail();
}

TEST(Dtls, GarbageIsIgnoredBeforeAndAfterTheHandshake) {
    Peers p;
    DtlsEndpoint server(*p.server_context, DtlsRole::kServer, p.client_context->fingerprint());
    DtlsEndpoint client(*p.client_context, DtlsRole::kClient, p.server_context->fingerprint());
    const Bytes junk_record = {23, 0xfe, 0xfd, 0, 1, 0, 0, 0, 0, 0, 9, 0, 40, 1, 2, 3};  // claims 40 bytes, has 3
    server.feed(junk_record);
    server.feed(Bytes{22});
    server.feed(Bytes(2000, 0xAB));
    EXPECT_EQ(server.state(), DtlsState::kHandshaking);
    pump(client, server);
    ASSERT_TRUE(server.handshake_done()) << server.error_detail();
    server.feed(junk_record);
    server.feed(Bytes(300, 0x17));
    EXPECT_TRUE(server.take_received().empty());
    ASSERT_TRUE(client.send(text("still fine")));
    pump(client, server);
    const auto got = server.take_received();
    ASSERT_EQ(got.size(), 1u);
    EXPECT_EQ(got[0], text("still fine"));
}

TEST(Dtls, CloseNotifyClosesThePeer) {
    Peers p;
    DtlsEndpoint server(*p.server_context, DtlsRole::kServer, p.client_context->fingerprint());
    DtlsEndpoint client(*p.client_context, DtlsRole::kClient, p.server_context->fingerprint());
    pump(client, server);
    ASSERT_TRUE(server.handshake_done());
    client.close();
    EXPECT_EQ(client.state(), DtlsState::kClosed);
    pump(client, server);
    EXPECT_EQ(server.state(), DtlsState::kClosed);
    EXPECT_EQ(server.error(), DtlsError::kNone);
}

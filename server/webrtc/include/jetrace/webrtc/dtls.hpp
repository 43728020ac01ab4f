// DTLS 1.2 (RFC 6347) as WebRTC uses it (RFC 8827): each side has a
// self-signed certificate whose SHA-256 fingerprint travels in the SDP; a
// peer's certificate is accepted when its fingerprint is the one its SDP
// gave, whoever signed it. OpenSSL runs over memory BIOs: the caller feeds
// received datagrams and sends what take_outgoing() returns, so no socket
// and no thread is OpenSSL's.
//
// Time: the caller decides when retransmission timers are checked
// (handle_timeout(), next_timeout()), but OpenSSL measures how long a timer
// has run with its own clock (the system's real time).
#pragma once

#include "jetrace/webrtc/sdp.hpp"

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

typedef struct ssl_ctx_st SSL_CTX;
typedef struct ssl_st SSL;
typedef struct bio_st BIO;
typedef struct x509_store_ctx_st X509_STORE_CTX;

namespace jetrace::webrtc {

namespace detail {
/// OpenSSL's certificate check of every endpoint: the fingerprint comparison.
int verify_peer_certificate(X509_STORE_CTX* store, void* arg);
}  // namespace detail

struct DtlsSettings {
    /// The largest datagram DTLS writes (unit: bytes): handshake messages
    /// are fragmented to fit it; each record is one datagram.
    std::size_t mtu_bytes = 1200;
    /// The certificate is valid from an hour ago for this long (unit: days).
    int certificate_days = 30;
    /// A handshake flight not answered is sent again after this, doubling
    /// each time up to max_retransmit_ms (unit: ms).
    std::uint32_t initial_retransmit_ms = 400;
    std::uint32_t max_retransmit_ms = 8000;
};

/// One certificate and its OpenSSL context, shared by every endpoint of the
/// server (and one in each test client).
class DtlsContext {
public:
    /// A context with a fresh self-signed ECDSA P-256 certificate;
    /// nullptr (and the reason in *error) if OpenSSL fails.
    static std::unique_ptr<DtlsContext> create(const DtlsSettings& settings, std::string* error = nullptr);
    ~DtlsContext();
    DtlsContext(const DtlsContext&) = delete;
    DtlsContext& operator=(const DtlsContext&) = delete;

    /// SHA-256 of the certificate's DER: the SDP's a=fingerprint:sha-256.
    const Sha256Fingerprint& fingerprint() const { return fingerprint_; }
    /// The certificate (DER), for tests and logs.
    const std::vector<std::uint8_t>& certificate_der() const { return der_; }
    const DtlsSettings& settings() const { return settings_; }
    SSL_CTX* native() const { return ctx_; }

private:
    DtlsContext() = default;
    SSL_CTX* ctx_ = nullptr;
    Sha256Fingerprint fingerprint_{};
    std::vector<std::uint8_t> der_;
    DtlsSettings settings_;
};

/// RFC 7983's demultiplexing test: a DTLS record starts with 20..63.
inline bool is_dtls(std::span<const std::uint8_t> datagram) {
    return !datagram.empty() && datagram[0] >= 20 && datagram[0] <= 63;
}

enum class DtlsRole : std::uint8_t { kServer, kClient };
enum class DtlsState : std::uint8_t { kHandshaking, kConnected, kFailed, kClosed };

enum class DtlsError : std::uint8_t {
    kNone = 0,
    kFingerprintMismatch,  ///< the peer's certificate is not the one its SDP named
    kHandshakeFailed,      ///< OpenSSL refused the handshake (error_detail() says why)
    kTimedOut,             ///< too many retransmissions without an answer
    kProtocolError,        ///< a fatal error after the handshake
};

std::string_view to_string(DtlsError error);

/// One DTLS association. Datagrams in: feed(); out: take_outgoing().
class DtlsEndpoint {
public:
    /// `context` must outlive the endpoint. A client sends its ClientHello at once.
    DtlsEndpoint(DtlsContext& context, DtlsRole role, const Sha256Fingerprint& peer_fingerprint);
    ~DtlsEndpoint();
    DtlsEndpoint(const DtlsEndpoint&) = delete;
    DtlsEndpoint& operator=(const DtlsEndpoint&) = delete;

    /// One received datagram (untrusted): handshake records, or application
    /// data for take_received(). Ignored once failed or closed.
    void feed(std::span<const std::uint8_t> datagram);
    /// The datagrams to send, each at most mtu_bytes, in order.
    std::vector<std::vector<std::uint8_t>> take_outgoing();
    /// Application data received since the last call, one record each.
    std::vector<std::vector<std::uint8_t>> take_received();
    /// Sends one record of application data; false unless connected, or if
    /// it does not fit one datagram (the payload is at most about mtu - 40 bytes).
    bool send(std::span<const std::uint8_t> data);
    /// Sends close_notify; the endpoint is then closed.
    void close();

    /// Time until handle_timeout() has work, while a handshake flight waits for an answer.
    std::optional<std::chrono::milliseconds> next_timeout() const;
    /// Retransmits the last flight if its timer expired; fails after too many.
    void handle_timeout();

    DtlsState state() const { return state_; }
    bool handshake_done() const { return state_ == DtlsState::kConnected; }
    DtlsError error() const { return error_; }
    /// OpenSSL's reason for a failure, "" otherwise.
    const std::string& error_detail() const { return detail_; }

private:
    friend int detail::verify_peer_certificate(X509_STORE_CTX* store, void* arg);
    void drive_handshake();
    void read_records();
    void fail(DtlsError error, int ssl_result);

    SSL* ssl_ = nullptr;
    BIO* in_ = nullptr;   // owned by ssl_
    BIO* out_ = nullptr;  // owned by ssl_
    Sha256Fingerprint peer_fingerprint_{};
    bool fingerprint_mismatch_ = false;
    DtlsState state_ = DtlsState::kHandshaking;
    DtlsError error_ = DtlsError::kNone;
    std::string detail_;
    std::vector<std::vector<std::uint8_t>> received_;
    std::vector<std::uint8_t> read_buffer_;  // one record's plaintext, allocated once
};

}  // namespace jetrace::webrtc

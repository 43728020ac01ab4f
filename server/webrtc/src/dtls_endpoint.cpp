// One DTLS association over memory BIOs: the handshake, the peer's
// fingerprint check, retransmission timers, application records.
#include "jetrace/webrtc/dtls.hpp"

#include "byte_io.hpp"

#include <openssl/crypto.h>
#include <openssl/err.h>
#include <openssl/evp.h>
#include <openssl/ssl.h>
#include <openssl/x509.h>

#include <algorithm>
#include <utility>
#include <sys/time.h>

namespace jetrace::webrtc {

namespace {

constexpr std::size_t kRecordHeaderBytes = 13;  // type, version, epoch, sequence number, length
constexpr std::size_t kMaxDatagramBytes = 65535;
constexpr std::size_t kMaxPlaintextBytes = 16384;

// The retransmission timer: the first wait, then doubling up to the maximum
// (OpenSSL passes the last wait, 0 at first; unit: us).
unsigned int retransmit_timer(SSL* ssl, unsigned int last_us) {
    const auto* context = static_cast<const DtlsContext*>(SSL_CTX_get_app_data(SSL_get_SSL_CTX(ssl)));
    const DtlsSettings& s = context->settings();
    if (last_us == 0) return s.initial_retransmit_ms * 1000u;
    const unsigned long long next = 2ull * last_us;
    return static_cast<unsigned int>(std::min<unsigned long long>(next, s.max_retransmit_ms * 1000ull));
}

// The first queued OpenSSL error as text (the queue is cleared).
std::string openssl_reason(int ssl_error) {
    std::string s;
    const unsigned long e = ERR_get_error();
    if (e != 0) {
        char buf[256];
        ERR_error_string_n(e, buf, sizeof buf);
        s = buf;
    } else {
        s = "SSL error " + std::to_string(ssl_error);
    }
    ERR_clear_error();
    return s;
}

}  // namespace

namespace detail {

int verify_peer_certificate(X509_STORE_CTX* store, void* /*arg*/) {
    auto* ssl = static_cast<SSL*>(X509_STORE_CTX_get_ex_data(store, SSL_get_ex_data_X509_STORE_CTX_idx()));
    auto* self = ssl != nullptr ? static_cast<DtlsEndpoint*>(SSL_get_app_data(ssl)) : nullptr;
    X509* cert = X509_STORE_CTX_get0_cert(store);
    if (self == nullptr || cert == nullptr) return 0;
    Sha256Fingerprint digest{};
    unsigned int n = 0;
    if (X509_digest(cert, EVP_sha256(), digest.data(), &n) != 1 || n != digest.size()) return 0;
    if (CRYPTO_memcmp(digest.data(), self->peer_fingerprint_.data(), digest.size()) != 0) {
        self->fingerprint_mismatch_ = true;
        X509_STORE_CTX_set_error(store, X509_V_ERR_CERT_REJECTED);
        return 0;
    }
    return 1;
}

}  // namespace detail

DtlsEndpoint::DtlsEndpoint(DtlsContext& context, DtlsRole role, const Sha256Fingerprint& peer_fingerprint)
    : peer_fingerprint_(peer_fingerprint) {
    ssl_ = SSL_new(context.native());
    in_ = BIO_new(BIO_s_mem());
    out_ = BIO_new(BIO_s_mem());
    if (ssl_ == nullptr || in_ == nullptr || out_ == nullptr) {
        BIO_free(in_);
        BIO_free(out_);
        in_ = out_ = nullptr;
        fail(DtlsError::kHandshakeFailed, 0);
        return;
    }
    // An empty BIO means "no datagram yet", not end of file.
    BIO_set_mem_eof_return(in_, -1);
    BIO_set_mem_eof_return(out_, -1);
    SSL_set_bio(ssl_, in_, out_);
    SSL_set_app_data(ssl_, this);
    SSL_set_options(ssl_, SSL_OP_NO_QUERY_MTU);
    DTLS_set_link_mtu(ssl_, static_cast<long>(context.settings().mtu_bytes));
    DTLS_set_timer_cb(ssl_, retransmit_timer);
    if (role == DtlsRole::kServer) {
        SSL_set_accept_state(ssl_);
    } else {
        SSL_set_connect_state(ssl_);
        drive_handshake();
    }
}

DtlsEndpoint::~DtlsEndpoint() { SSL_free(ssl_); }  // frees both BIOs

void DtlsEndpoint::feed(std::span<const std::uint8_t> datagram) {
    if (ssl_ == nullptr || state_ == DtlsState::kFailed || state_ == DtlsState::kClosed) return;
    if (datagram.empty() || datagram.size() > kMaxDatagramBytes) return;
    BIO_write(in_, datagram.data(), static_cast<int>(datagram.size()));
    if (state_ == DtlsState::kHandshaking) {
        drive_handshake();
    } else {
        read_records();
    }
    // What OpenSSL left unread (a record cut short) must not join the next datagram.
    if (BIO_ctrl_pending(in_) > 0) (void)BIO_reset(in_);
}

void DtlsEndpoint::drive_handshake() {
    ERR_clear_error();
    const int r = SSL_do_handshake(ssl_);
    if (r == 1) {
        state_ = DtlsState::kConnected;
        read_records();  // application data in the same datagram as the last flight
        return;
    }
    const int e = SSL_get_error(ssl_, r);
    if (e == SSL_ERROR_WANT_READ || e == SSL_ERROR_WANT_WRITE) return;
    fail(fingerprint_mismatch_ ? DtlsError::kFingerprintMismatch : DtlsError::kHandshakeFailed, e);
}

void DtlsEndpoint::read_records() {
    if (read_buffer_.empty()) read_buffer_.resize(kMaxPlaintextBytes);
    for (;;) {
        ERR_clear_error();
        const int n = SSL_read(ssl_, read_buffer_.data(), static_cast<int>(read_buffer_.size()));
        if (n > 0) {
            received_.emplace_back(read_buffer_.begin(), read_buffer_.begin() + n);
            continue;
        }
        const int e = SSL_get_error(ssl_, n);
        if (e == SSL_ERROR_WANT_READ || e == SSL_ERROR_WANT_WRITE) return;
        if (e == SSL_ERROR_ZERO_RETURN) {
            state_ = DtlsState::kClosed;  // close_notify
            return;
        }
        fail(DtlsError::kProtocolError, e);
        return;
    }
}

void DtlsEndpoint::fail(DtlsError error, int ssl_error) {
    state_ = DtlsState::kFailed;
    error_ = error;
    detail_ = openssl_reason(ssl_error);
}

std::vector<std::vector<std::uint8_t>> DtlsEndpoint::take_outgoing() {
    std::vector<std::vector<std::uint8_t>> out;
    if (out_ == nullptr) return out;
    const std::size_t pending = BIO_ctrl_pending(out_);
    if (pending == 0) return out;
    std::vector<std::uint8_t> bytes(pending);
    const int got = BIO_read(out_, bytes.data(), static_cast<int>(bytes.size()));
    bytes.resize(got > 0 ? static_cast<std::size_t>(got) : 0);
    // The memory BIO joins OpenSSL's writes, each one record (a handshake
    // message fragment, ChangeCipherSpec, an alert, application data): they
    // are split again into one datagram each, as OpenSSL sends them over a
    // socket. (Packing a flight into one datagram is allowed, but OpenSSL as
    // a receiver drops the rest of a datagram after a record it answers with
    // a retransmission, such as a repeated ClientHello.)
    std::size_t at = 0;
    while (at < bytes.size()) {
        const std::size_t left = bytes.size() - at;
        const std::size_t record =
            left >= kRecordHeaderBytes ? std::min(left, kRecordHeaderBytes + detail::load_u16(bytes, at + 11)) : left;
        out.emplace_back(bytes.begin() + static_cast<std::ptrdiff_t>(at),
                         bytes.begin() + static_cast<std::ptrdiff_t>(at + record));
        at += record;
    }
    return out;
}

std::vector<std::vector<std::uint8_t>> DtlsEndpoint::take_received() { return std::exchange(received_, {}); }

bool DtlsEndpoint::send(std::span<const std::uint8_t> data) {
    if (state_ != DtlsState::kConnected || data.empty() || data.size() > DTLS_get_data_mtu(ssl_)) return false;
    ERR_clear_error();
    const int n = SSL_write(ssl_, data.data(), static_cast<int>(data.size()));
    if (n == static_cast<int>(data.size())) return true;
    fail(DtlsError::kProtocolError, SSL_get_error(ssl_, n));
    return false;
}

void DtlsEndpoint::close() {
    if (ssl_ == nullptr || state_ == DtlsState::kFailed || state_ == DtlsState::kClosed) return;
    ERR_clear_error();
    SSL_shutdown(ssl_);
    ERR_clear_error();
    state_ = DtlsState::kClosed;
}

std::optional<std::chrono::milliseconds> DtlsEndpoint::next_timeout() const {
    if (ssl_ == nullptr || state_ == DtlsState::kFailed || state_ == DtlsState::kClosed) return std::nullopt;
    timeval tv{};
    if (DTLSv1_get_timeout(ssl_, &tv) != 1) return std::nullopt;
    return std::chrono::milliseconds(static_cast<long long>(tv.tv_sec) * 1000 + (tv.tv_usec + 999) / 1000);
}

void DtlsEndpoint::handle_timeout() {
    if (ssl_ == nullptr || state_ == DtlsState::kFailed || state_ == DtlsState::kClosed) return;
    ERR_clear_error();
    if (DTLSv1_handle_timeout(ssl_) < 0) fail(DtlsError::kTimedOut, 0);
}

std::string_view to_string(DtlsError error) {
    switch (error) {
        case DtlsError::kNone: return "ok";
        case DtlsError::kFingerprintMismatch: return "peer certificate fingerprint mismatch";
        case DtlsError::kHandshakeFailed: return "handshake failed";
        case DtlsError::kTimedOut: return "handshake timed out";
        case DtlsError::kProtocolError: return "protocol error";
    }
    return "unknown DTLS error";
}

}  // namespace jetrace::webrtc

// The DTLS context: a self-signed ECDSA P-256 certificate made at start, its
// fingerprint, and the OpenSSL settings every endpoint shares.
#include "jetrace/webrtc/dtls.hpp"

#include <openssl/err.h>
#include <openssl/evp.h>
#include <openssl/rand.h>
#include <openssl/ssl.h>
#include <openssl/x509.h>

#include <algorithm>

namespace jetrace::webrtc {

namespace {

// ECDHE with ECDSA only: what browsers offer for WebRTC's DTLS 1.2.
constexpr const char* kCiphers =
    "ECDHE-ECDSA-AES128-GCM-SHA256:ECDHE-ECDSA-AES256-GCM-SHA384:ECDHE-ECDSA-CHACHA20-POLY1305";
constexpr const char* kGroups = "X25519:P-256:P-384";

struct KeyFree {
    void operator()(EVP_PKEY* k) const { EVP_PKEY_free(k); }
};
struct CertFree {
    void operator()(X509* x) const { X509_free(x); }
};
using KeyPtr = std::unique_ptr<EVP_PKEY, KeyFree>;
using CertPtr = std::unique_ptr<X509, CertFree>;

std::string openssl_error(const char* what) {
    std::string s = what;
    const unsigned long e = ERR_get_error();
    if (e != 0) {
        char buf[256];
        ERR_error_string_n(e, buf, sizeof buf);
        s += ": ";
        s += buf;
    }
    ERR_clear_error();
    return s;
}

// A self-signed X.509 v3 certificate for `key`, CN=jetrace, valid from an
// hour ago (clock skew) for `days`, with a random 63-bit serial.
CertPtr self_signed(EVP_PKEY* key, int days) {
    CertPtr x(X509_new());
    std::uint64_t serial = 0;
    if (!x || RAND_bytes(reinterpret_cast<unsigned char*>(&serial), sizeof serial) != 1) return nullptr;
    X509_NAME* name = X509_get_subject_name(x.get());
    const auto* cn = reinterpret_cast<const unsigned char*>("jetrace");
    const bool ok = X509_set_version(x.get(), 2) == 1 &&
                    ASN1_INTEGER_set_uint64(X509_get_serialNumber(x.get()), serial >> 1) == 1 &&
                    X509_gmtime_adj(X509_getm_notBefore(x.get()), -3600) != nullptr &&
                    X509_gmtime_adj(X509_getm_notAfter(x.get()), static_cast<long>(days) * 86400) != nullptr &&
                    X509_set_pubkey(x.get(), key) == 1 &&
                    X509_NAME_add_entry_by_txt(name, "CN", MBSTRING_ASC, cn, -1, -1, 0) == 1 &&
                    X509_set_issuer_name(x.get(), name) == 1 && X509_sign(x.get(), key, EVP_sha256()) > 0;
    return ok ? std::move(x) : nullptr;
}

}  // namespace

std::unique_ptr<DtlsContext> DtlsContext::create(const DtlsSettings& settings, std::string* error) {
    std::unique_ptr<DtlsContext> c(new DtlsContext());
    c->settings_ = settings;
    const auto failed = [&](const char* what) {
        if (error) *error = openssl_error(what);
        return nullptr;
    };
    KeyPtr key(EVP_EC_gen("P-256"));
    if (!key) return failed("EC key generation");
    CertPtr cert = self_signed(key.get(), settings.certificate_days);
    if (!cert) return failed("self-signed certificate");
    unsigned int md_len = 0;
    if (X509_digest(cert.get(), EVP_sha256(), c->fingerprint_.data(), &md_len) != 1 || md_len != 32)
        return failed("certificate digest");
    const int der_len = i2d_X509(cert.get(), nullptr);
    if (der_len <= 0) return failed("certificate DER");
    c->der_.resize(static_cast<std::size_t>(der_len));
    unsigned char* p = c->der_.data();
    i2d_X509(cert.get(), &p);
    c->ctx_ = SSL_CTX_new(DTLS_method());
    if (!c->ctx_) return failed("SSL_CTX_new");
    SSL_CTX* ctx = c->ctx_;
    SSL_CTX_set_app_data(ctx, c.get());
    const bool ok = SSL_CTX_set_min_proto_version(ctx, DTLS1_2_VERSION) == 1 &&
                    SSL_CTX_set_cipher_list(ctx, kCiphers) == 1 && SSL_CTX_set1_groups_list(ctx, kGroups) == 1 &&
                    SSL_CTX_use_certificate(ctx, cert.get()) == 1 && SSL_CTX_use_PrivateKey(ctx, key.get()) == 1 &&
                    SSL_CTX_check_private_key(ctx) == 1;
    if (!ok) return failed("SSL_CTX setup");
    SSL_CTX_set_options(ctx, SSL_OP_NO_QUERY_MTU | SSL_OP_NO_TICKET | SSL_OP_NO_RENEGOTIATION);
    // Any certificate is accepted by the chain check; its fingerprint is compared instead.
    SSL_CTX_set_verify(ctx, SSL_VERIFY_PEER | SSL_VERIFY_FAIL_IF_NO_PEER_CERT, nullptr);
    SSL_CTX_set_cert_verify_callback(ctx, &detail::verify_peer_certificate, nullptr);
    return c;
}

DtlsContext::~DtlsContext() { SSL_CTX_free(ctx_); }

}  // namespace jetrace::webrtc

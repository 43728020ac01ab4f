// Reading the browser's SDP offer: one data-channel section, its ICE
// credentials, DTLS fingerprint and role, mid and SCTP parameters.
#include "jetrace/webrtc/sdp.hpp"

#include "sdp_text.hpp"

#include <optional>

namespace jetrace::webrtc {

namespace {

using detail::ice_chars;
using detail::parse_decimal;

// The attributes read at one level: the session's, or the data channel's.
struct Level {
    std::optional<std::string> ufrag, pwd, mid;
    std::optional<Sha256Fingerprint> fingerprint;
    std::optional<SdpSetup> setup;
    std::optional<std::uint16_t> sctp_port;
    std::optional<std::uint32_t> max_message_size;
};

struct OfferReader {
    Level session;
    Level media;
    bool in_media = false;  // after the data channel's m= line
};

bool token_chars(std::string_view s) {
    constexpr std::string_view kExtra = "!#$%&'*+-.^_`{|}~";
    for (const char c : s) {
        const bool alnum = (c >= '0' && c <= '9') || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
        if (!alnum && kExtra.find(c) == std::string_view::npos) return false;
    }
    return true;
}

bool iequals(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const auto lower = [](char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; };
        if (lower(a[i]) != lower(b[i])) return false;
    }
    return true;
}

int hex_digit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

// "AB:CD:..." with exactly 32 bytes.
bool parse_fingerprint_hex(std::string_view hex, Sha256Fingerprint& out) {
    if (hex.size() != out.size() * 3 - 1) return false;
    for (std::size_t i = 0; i < out.size(); ++i) {
        const int hi = hex_digit(hex[3 * i]);
        const int lo = hex_digit(hex[3 * i + 1]);
        if (hi < 0 || lo < 0 || (i + 1 < out.size() && hex[3 * i + 2] != ':')) return false;
        out[i] = static_cast<std::uint8_t>(hi * 16 + lo);
    }
    return true;
}

// "m=application 9 UDP/DTLS/SCTP webrtc-datachannel": the only section accepted.
SdpError read_media_line(std::string_view value, OfferReader& r) {
    const auto fields = detail::split_spaces(value);
    std::uint64_t port = 0;
    if (fields.size() < 4 || !parse_decimal(fields[1], 65535, port)) return SdpError::kMalformedLine;
    const bool data_channel = fields.size() == 4 && fields[0] == "application" && fields[2] == "UDP/DTLS/SCTP" &&
                              fields[3] == "webrtc-datachannel";
    if (!data_channel || r.in_media) return SdpError::kUnsupportedMedia;
    r.in_media = true;
    return SdpError::kNone;
}

template <typename T>
SdpError set_once(std::optional<T>& slot, T value) {
    if (slot) return SdpError::kDuplicateAttribute;
    slot = std::move(value);
    return SdpError::kNone;
}

SdpError read_fingerprint(std::string_view value, Level& level) {
    const std::size_t space = value.find(' ');
    if (space == std::string_view::npos) return SdpError::kBadFingerprint;
    if (!iequals(value.substr(0, space), "sha-256")) return SdpError::kNone;  // other hashes: not used
    Sha256Fingerprint fp{};
    if (!parse_fingerprint_hex(value.substr(space + 1), fp)) return SdpError::kBadFingerprint;
    return set_once(level.fingerprint, fp);
}

SdpError read_setup(std::string_view value, Level& level) {
    if (value == "actpass") return set_once(level.setup, SdpSetup::kActpass);
    if (value == "active") return set_once(level.setup, SdpSetup::kActive);
    return SdpError::kBadSetup;  // passive or holdconn: the browser would have to be the DTLS server
}

// One a= line (name, value) at the current level.
SdpError read_attribute(std::string_view name, std::string_view value, OfferReader& r) {
    Level& level = r.in_media ? r.media : r.session;
    std::uint64_t n = 0;
    if (name == "ice-ufrag") {
        if (!ice_chars(value, kMinUfragChars, kMaxIceCredentialChars)) return SdpError::kBadIceUfrag;
        return set_once(level.ufrag, std::string(value));
    }
    if (name == "ice-pwd") {
        if (!ice_chars(value, kMinPwdChars, kMaxIceCredentialChars)) return SdpError::kBadIcePwd;
        return set_once(level.pwd, std::string(value));
    }
    if (name == "fingerprint") return read_fingerprint(value, level);
    if (name == "setup") return read_setup(value, level);
    if (!r.in_media) return SdpError::kNone;  // the rest are media-level only
    if (name == "mid") {
        if (value.empty() || value.size() > kMaxMidChars || !token_chars(value)) return SdpError::kBadMid;
        return set_once(level.mid, std::string(value));
    }
    if (name == "sctp-port") {
        if (!parse_decimal(value, 65535, n) || n == 0) return SdpError::kBadSctpPort;
        return set_once(level.sctp_port, static_cast<std::uint16_t>(n));
    }
    if (name == "max-message-size") {
        if (!parse_decimal(value, 0xFFFFFFFFu, n)) return SdpError::kBadMaxMessageSize;
        return set_once(level.max_message_size, static_cast<std::uint32_t>(n));
    }
    return SdpError::kNone;
}

SdpError read_line(std::string_view line, OfferReader& r) {
    const char type = line[0];
    const std::string_view value = line.substr(2);
    if (type == 'm') return read_media_line(value, r);
    if (type != 'a') return SdpError::kNone;
    const std::size_t colon = value.find(':');
    if (colon == std::string_view::npos) return SdpError::kNone;  // flags: a=ice-lite, a=extmap-allow-mixed...
    return read_attribute(value.substr(0, colon), value.substr(colon + 1), r);
}

// The section's attribute, else the session's.
template <typename T>
std::optional<T> pick(const std::optional<T>& media, const std::optional<T>& session) {
    return media ? media : session;
}

SdpError finish(const OfferReader& r, SdpOffer& out) {
    if (!r.in_media) return SdpError::kNoDataChannel;
    const auto ufrag = pick(r.media.ufrag, r.session.ufrag);
    const auto pwd = pick(r.media.pwd, r.session.pwd);
    if (!ufrag || !pwd) return SdpError::kNoIceCredentials;
    const auto fp = pick(r.media.fingerprint, r.session.fingerprint);
    if (!fp) return SdpError::kNoFingerprint;
    out.ice_ufrag = *ufrag;
    out.ice_pwd = *pwd;
    out.fingerprint = *fp;
    out.setup = pick(r.media.setup, r.session.setup).value_or(SdpSetup::kActpass);
    out.mid = r.media.mid.value_or("");
    out.sctp_port = r.media.sctp_port.value_or(5000);
    out.max_message_size = r.media.max_message_size.value_or(65536);
    return SdpError::kNone;
}

}  // namespace

SdpError parse_offer(std::string_view text, SdpOffer& out, std::size_t* error_line) {
    out = SdpOffer{};
    if (error_line) *error_line = 0;
    if (text.size() > kMaxOfferBytes) return SdpError::kTooLarge;
    OfferReader r;
    std::size_t number = 0;
    std::string_view line;
    while (detail::next_line(text, line)) {
        ++number;
        SdpError e = SdpError::kNone;
        if (!detail::well_formed_line(line) || (number == 1 && line != "v=0")) {
            e = SdpError::kMalformedLine;
        } else {
            e = read_line(line, r);
        }
        if (e != SdpError::kNone) {
            if (error_line) *error_line = number;
            return e;
        }
    }
    if (number == 0) return SdpError::kMalformedLine;
    return finish(r, out);
}

}  // namespace jetrace::webrtc

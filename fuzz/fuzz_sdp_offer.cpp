// An SDP offer as the web port's signalling POST receives it
// (webrtc::parse_offer), and the answer written to an accepted one.
// Invariants: an accepted offer has RFC 8839 credentials and a mid of token
// characters (echoed into the answer); the answer is lines of printable
// text, each ended by CRLF, with the offer's mid and nothing of its other text.
#include "fuzz_check.hpp"
#include "jetrace/webrtc/sdp.hpp"

#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace jetrace::webrtc;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    SdpOffer offer;
    std::size_t line = 0;
    const SdpError error = parse_offer(text, offer, &line);
    JETRACE_FUZZ_CHECK(!to_string(error).empty());
    if (error != SdpError::kNone) {
        JETRACE_FUZZ_CHECK(size > kMaxOfferBytes || line <= size + 1);
        return 0;
    }
    JETRACE_FUZZ_CHECK(size <= kMaxOfferBytes && line == 0);
    JETRACE_FUZZ_CHECK(offer.ice_ufrag.size() >= kMinUfragChars && offer.ice_ufrag.size() <= kMaxIceCredentialChars);
    JETRACE_FUZZ_CHECK(offer.ice_pwd.size() >= kMinPwdChars && offer.ice_pwd.size() <= kMaxIceCredentialChars);
    JETRACE_FUZZ_CHECK(offer.mid.size() <= kMaxMidChars && offer.setup != SdpSetup::kPassive);
    AnswerSettings s;
    s.ice = make_ice_credentials([](std::span<std::uint8_t> out) {
        for (auto& b : out) b = 0x5a;
    });
    s.candidate_ip = "192.0.2.1";
    s.candidate_port = 7779;
    const std::string answer = write_answer(offer, s);
    JETRACE_FUZZ_CHECK(answer.size() >= 2 && answer.compare(answer.size() - 2, 2, "\r\n") == 0);
    for (std::size_t i = 0; i < answer.size(); ++i) {
        const auto c = static_cast<unsigned char>(answer[i]);
        JETRACE_FUZZ_CHECK(c >= 0x20 ? c < 0x7f : (c == '\r' ? answer[i + 1] == '\n' : c == '\n' && answer[i - 1] == '\r'));
    }
    JETRACE_FUZZ_CHECK(offer.mid.empty() || answer.find("a=mid:" + offer.mid + "\r\n") != std::string::npos);
    return 0;
}

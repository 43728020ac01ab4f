// What the web port's I/O thread and the server's loop share in the WebRTC
// transport: offers answered and waiting for the loop (the inbox), and the
// counts the caps need (pending handshakes overall and per address,
// sessions). Everything is behind `mutex_`; every function takes it.
#pragma once

#include "jetrace/rtc/rtc_transport.hpp"
#include "jetrace/webrtc/sdp.hpp"

#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace jetrace::rtc::detail {

/// An offer the signalling answered, for the loop to take up.
struct PendingOffer {
    std::string address;  ///< the POST's IP (its pending count)
    webrtc::IceCredentials ice;
    webrtc::SdpOffer offer;
};

class SignalState final : public RtcSignal {
public:
    SignalState(RtcConfig config, const webrtc::Sha256Fingerprint& fingerprint, std::uint16_t port);

    RtcReply offer(std::string_view sdp, const std::string& address, const std::string& local_ip) override;

    /// The offers answered since the last call.
    std::vector<PendingOffer> take_inbox();
    /// A pending session of `address` opened its channels, or was dropped
    /// before (`expired`): it no longer counts against the pending caps.
    void settled(const std::string& address, bool expired);
    /// A session (pending or not) is gone.
    void ended();
    /// The transport is gone: every later offer is answered 503.
    void close();

    void count_rate_limited(std::uint64_t n);
    void count_sent_reliably();
    RtcStats stats() const;

private:
    RtcReply refuse(int status, std::string reason);

    const RtcConfig config_;
    const webrtc::Sha256Fingerprint fingerprint_;
    const std::uint16_t port_;
    mutable std::mutex mutex_;
    bool closed_ = false;
    std::vector<PendingOffer> inbox_;
    std::map<std::string, std::size_t> pending_by_address_;
    std::size_t pending_ = 0;
    std::size_t sessions_ = 0;
    RtcStats stats_;
};

}  // namespace jetrace::rtc::detail

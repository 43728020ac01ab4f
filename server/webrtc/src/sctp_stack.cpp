// usrsctp's initialisation (no threads), its callbacks, and the table of
// associations by AF_CONN address.
#include "sctp_stack.hpp"

#include <usrsctp.h>

#include <arpa/inet.h>

#include <cstdlib>
#include <unordered_map>

namespace jetrace::webrtc {

namespace detail {

int SctpCallbacks::output(void* addr, void* buffer, std::size_t length, std::uint8_t /*tos*/, std::uint8_t /*set_df*/) {
    SctpAssociation* a = find_association(reinterpret_cast<std::uintptr_t>(addr));
    if (a != nullptr) {
        const auto* p = static_cast<const std::uint8_t*>(buffer);
        a->outgoing_.emplace_back(p, p + length);
    }
    return 0;
}

int SctpCallbacks::receive(struct socket* /*sock*/, union sctp_sockstore /*addr*/, void* data, std::size_t length,
                           struct sctp_rcvinfo info, int flags, void* ulp_info) {
    SctpAssociation* a = find_association(reinterpret_cast<std::uintptr_t>(ulp_info));
    if (a != nullptr && data == nullptr) {
        if (a->state_ != SctpState::kFailed) a->state_ = SctpState::kClosed;  // the association ended
    } else if (a != nullptr) {
        const std::span<const std::uint8_t> bytes(static_cast<const std::uint8_t*>(data), length);
        if ((flags & MSG_NOTIFICATION) != 0) {
            a->on_notification(bytes);
        } else {
            a->on_receive(bytes, info.rcv_sid, ntohl(info.rcv_ppid), (info.rcv_flags & SCTP_UNORDERED) != 0,
                          (flags & MSG_EOR) != 0);
        }
    }
    std::free(data);
    return 1;
}

namespace {

std::unordered_map<std::uintptr_t, SctpAssociation*>& table() {
    static std::unordered_map<std::uintptr_t, SctpAssociation*> associations;
    return associations;
}

bool initialised = false;

void initialise(const SctpGlobals& g) {
    if (initialised) return;
    initialised = true;
    usrsctp_init_nothreads(0, &SctpCallbacks::output, nullptr);
    usrsctp_sysctl_set_sctp_ecn_enable(0);  // no ECN bits through DTLS
    // No address changes to announce (ASCONF): nothing for usrsctp's iterator
    // thread to do for these associations (see sctp.hpp).
    usrsctp_sysctl_set_sctp_asconf_enable(0);
    usrsctp_sysctl_set_sctp_auto_asconf(0);
    usrsctp_sysctl_set_sctp_rto_min_default(g.rto_min_ms);
    usrsctp_sysctl_set_sctp_rto_max_default(g.rto_max_ms);
    usrsctp_sysctl_set_sctp_rto_initial_default(g.rto_initial_ms);
    usrsctp_sysctl_set_sctp_init_rto_max_default(g.rto_max_ms);
    usrsctp_sysctl_set_sctp_delayed_sack_time_default(g.delayed_sack_ms);
    usrsctp_sysctl_set_sctp_heartbeat_interval_default(g.heartbeat_interval_ms);
}

}  // namespace

std::uintptr_t register_association(SctpAssociation* association, const SctpGlobals& globals) {
    initialise(globals);
    static std::uintptr_t next_id = 1;
    const std::uintptr_t id = next_id++;
    table()[id] = association;
    usrsctp_register_address(reinterpret_cast<void*>(id));
    return id;
}

void unregister_association(std::uintptr_t id) {
    usrsctp_deregister_address(reinterpret_cast<void*>(id));
    table().erase(id);
}

SctpAssociation* find_association(std::uintptr_t id) {
    const auto it = table().find(id);
    return it == table().end() ? nullptr : it->second;
}

}  // namespace detail

void SctpAssociation::advance_timers(std::uint32_t elapsed_ms) {
    if (detail::initialised) usrsctp_handle_timers(elapsed_ms);
}

}  // namespace jetrace::webrtc

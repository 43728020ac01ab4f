// usrsctp as a process-wide singleton: initialised once without threads,
// and the table that maps each AF_CONN address (an id) to its association,
// which its output and receive callbacks go through.
#pragma once

#include "jetrace/webrtc/sctp.hpp"

#include <usrsctp.h>

#include <cstdint>

namespace jetrace::webrtc::detail {

/// usrsctp's callbacks, which reach an association's private state.
struct SctpCallbacks {
    /// usrsctp has a packet for the peer of the association at `addr`.
    static int output(void* addr, void* buffer, std::size_t length, std::uint8_t tos, std::uint8_t set_df);
    /// A message (or a piece of one) or a notification; `data` is ours to free.
    static int receive(struct socket* sock, union sctp_sockstore addr, void* data, std::size_t length,
                       struct sctp_rcvinfo info, int flags, void* ulp_info);
};

/// Initialises usrsctp on first use (with `globals`), registers a fresh
/// AF_CONN address for `association` and returns it.
std::uintptr_t register_association(SctpAssociation* association, const SctpGlobals& globals);
/// Forgets the address: callbacks for it are dropped from now on.
void unregister_association(std::uintptr_t id);
/// The association of an address, nullptr if none.
SctpAssociation* find_association(std::uintptr_t id);

}  // namespace jetrace::webrtc::detail

// decode_jtrack() on untrusted bytes (what load_track() runs on a .jtrack
// file after mapping it). Each input is decoded twice: as it is, and with
// both CRC-32C fields recomputed over it, so that the fuzzer reaches the
// checks behind the checksums. Invariants: a refusal names its problem; an
// accepted track validates, encodes to bytes that decode to the same track
// (identity), and encoding is then a fixed point; a scene builds on it and
// a car spawned on it steps.
#include "fuzz_check.hpp"
#include "jetrace/core/crc32c.hpp"
#include "jetrace/core/world.hpp"
#include "jetrace/tracks/jtrack.hpp"

#include <vector>

namespace {

void put_u32(std::vector<std::uint8_t>& b, std::size_t at, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) b[at + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(v >> (8 * i));
}

void check(std::span<const std::uint8_t> bytes) {
    jetrace::Track track;
    std::string error;
    if (!jetrace::decode_jtrack(bytes, track, error)) {
        JETRACE_FUZZ_CHECK(!error.empty());
        return;
    }
    JETRACE_FUZZ_CHECK(jetrace::validate(track).empty());
    const std::vector<std::uint8_t> once = jetrace::encode_jtrack(track);
    jetrace::Track again;
    JETRACE_FUZZ_CHECK(jetrace::decode_jtrack(once, again, error));
    JETRACE_FUZZ_CHECK(again.identity() == track.identity() && again.name == track.name);
    JETRACE_FUZZ_CHECK(jetrace::encode_jtrack(again) == once);

    const jetrace::Scene scene = jetrace::Scene::make(std::move(track), jetrace::PhysicsSettings{});
    jetrace::World world(scene, jetrace::make_world(1, 1));
    jetrace::spawn_car(scene, world.state(), 0, 0);
    const jetrace::Input full = jetrace::Input::clamped(jetrace::Input::kMaxThrottle, 0, 0);
    for (int i = 0; i < 4; ++i) world.step(std::span(&full, 1));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    check(jetrace::fuzz::bytes(data, size));
    if (size >= jetrace::kJtrackHeaderBytes) {
        std::vector<std::uint8_t> sealed(data, data + size);
        put_u32(sealed, 56, jetrace::crc32c(std::span<const std::uint8_t>(sealed).subspan(64)));
        put_u32(sealed, 60, jetrace::crc32c(std::span<const std::uint8_t>(sealed.data(), 60)));
        check(sealed);
    }
    return 0;
}

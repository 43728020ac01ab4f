#include "jetrace/replay/diff.hpp"
#include "jetrace/replay/synctest.hpp"
#include "jetrace/replay/verify.hpp"

#include <nlohmann/json.hpp>

namespace jetrace::replay {

namespace {

nlohmann::json fields_json(const std::vector<FieldDifference>& fields, const char* a, const char* b) {
    nlohmann::json out = nlohmann::json::array();
    for (const FieldDifference& d : fields) out.push_back({{"slot", d.slot}, {"field", d.field}, {a, d.a}, {b, d.b}});
    return out;
}

std::string dump(const nlohmann::json& j) {
    // Names may hold any bytes: replace what is not UTF-8 rather than throw.
    return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

nlohmann::json results_json(const std::vector<ResultEntry>& results) {
    nlohmann::json out = nlohmann::json::array();
    for (const ResultEntry& r : results) {
        nlohmann::json e{{"slot", r.slot}, {"finished", r.finished}, {"lap", r.lap}, {"next_checkpoint", r.next_checkpoint}};
        if (r.finished) e["finish_time_s"] = r.finish_time_s;
        out.push_back(std::move(e));
    }
    return out;
}

}  // namespace

std::string to_json(const Verdict& v) {
    nlohmann::json j{
        {"ok", v.ok},
        {"track", v.track},
        {"race", v.race_number},
        {"initial_tick", v.initial_tick},
        {"final_tick", v.final_tick},
        {"state_hash", hash_hex(v.state_hash)},
        {"checkpoints", v.checkpoints},
        {"keyframes", v.keyframes},
        {"complete", v.complete},
        {"signature", v.signature},
        {"bytes", v.bytes},
    };
    if (v.complete) {
        j["end_reason"] = v.end_reason;
        j["results"] = results_json(v.results);
    }
    if (!v.signer.empty()) {
        j["signer"] = v.signer;
        j["signer_trusted"] = v.signer_trusted;
    }
    if (v.last_good_checkpoint) j["last_good_checkpoint"] = *v.last_good_checkpoint;
    if (!v.ok) {
        nlohmann::json f{{"problem", v.problem}, {"byte_offset", v.byte_offset}, {"tick", v.tick}, {"message", v.message}};
        if (!v.cars.empty()) f["cars"] = v.cars;
        if (v.fields_tick) {
            f["fields_tick"] = *v.fields_tick;
            f["fields"] = fields_json(v.fields, "recorded", "resimulated");
        }
        j["failure"] = std::move(f);
    }
    return dump(j);
}

std::string to_json(const DiffReport& d) {
    nlohmann::json j{{"verdict", d.verdict}, {"message", d.message}, {"ticks_compared", d.ticks_compared}};
    if (d.last_agreeing_tick) j["last_agreeing_tick"] = *d.last_agreeing_tick;
    if (d.first_differing_tick) {
        j["first_differing_tick"] = *d.first_differing_tick;
        j["cars"] = d.cars;
    }
    if (d.fields_tick) {
        j["fields_tick"] = *d.fields_tick;
        j["fields"] = fields_json(d.fields, "a", "b");
    }
    if (d.input_tick) {
        j["input_tick"] = *d.input_tick;
        j["input_slot"] = d.input_slot;
        j["input_a"] = d.input_a;
        j["input_b"] = d.input_b;
    }
    if (!d.this_build.empty()) j["this_build_matches"] = d.this_build;
    return dump(j);
}

std::string to_json(const SynctestReport& r) {
    nlohmann::json j{{"ok", r.ok}, {"ticks", r.ticks}, {"fresh_scratch_checks", r.fresh_checks},
                     {"rollback_checks", r.rollback_checks}, {"rollback_ticks", r.rollback_ticks}};
    if (!r.ok) {
        j["failure"] = {{"check", r.check}, {"tick", r.tick}, {"message", r.message},
                        {"fields", fields_json(r.fields, "first", "again")}};
    }
    return dump(j);
}

}  // namespace jetrace::replay

// jetrace-view's drive mode units: the keys message a driving page sends
// (every field checked, anything else refused) and the input it becomes.
#include "drive_messages.hpp"
#include "live_session.hpp"
#include "page_messages.hpp"

#include <gtest/gtest.h>

#include <string>

namespace jetrace::view {
namespace {

bool parses(const std::string& text, KeysMessage& k) {
    std::string error;
    const bool ok = parse_keys_message(text, k, error);
    EXPECT_EQ(ok, error.empty()) << text;
    return ok;
}

TEST(KeysMessages, AcceptsTheKeyboardState) {
    KeysMessage k;
    ASSERT_TRUE(parses(R"({"type":"keys","up":true,"left":false,"right":true,"brake":false})", k));
    EXPECT_EQ(k, (KeysMessage{true, false, true, false}));
    ASSERT_TRUE(parses(R"({"brake":true,"right":false,"left":true,"up":false,"type":"keys"})", k));
    EXPECT_EQ(k, (KeysMessage{false, true, false, true}));
}

TEST(KeysMessages, RejectsEverythingElse) {
    const std::string too_long =
        R"({"type":"keys","up":true,"left":false,"right":false,"brake":false,"x":")" + std::string(1024, 'a') + "\"}";
    for (const std::string& bad : {
             std::string(""), std::string("{"), std::string("[]"), std::string("null"), std::string(R"("keys")"),
             std::string(R"({"type":"play"})"), std::string(R"({"type":"seek","tick":1})"),
             std::string(R"({"type":"keys"})"),
             std::string(R"({"type":"keys","up":true,"left":false,"right":false})"),
             std::string(R"({"type":"keys","up":1,"left":false,"right":false,"brake":false})"),
             std::string(R"({"type":"keys","up":"true","left":false,"right":false,"brake":false})"),
             std::string(R"({"type":"keys","up":null,"left":false,"right":false,"brake":false})"),
             std::string(R"({"type":"keys","up":true,"left":false,"right":false,"brake":false,"x":0})"),
             std::string(R"({"type":"keys","up":true,"left":false,"right":false,"space":false})"),
             std::string(R"({"type":1,"up":true,"left":false,"right":false,"brake":false})"),
             std::string("{\"type\":\"keys\",\"up\":true,\"left\":false,\"right\":false,\"brake\":\xff}"),
             too_long,
         }) {
        KeysMessage k{true, true, true, true};
        std::string error;
        EXPECT_FALSE(parse_keys_message(bad, k, error)) << bad;
        EXPECT_FALSE(error.empty()) << bad;
        EXPECT_EQ(k, (KeysMessage{true, true, true, true})) << "unchanged by " << bad;
    }
}

TEST(KeysMessages, BecomeTheCarsInput) {
    EXPECT_EQ(input_of({}).pack(), Input{}.pack());
    const Input up = input_of({true, false, false, false});
    EXPECT_EQ(up.throttle, Input::kMaxThrottle);
    EXPECT_EQ(up.steer, 0);
    EXPECT_EQ(input_of({false, true, false, false}).steer, -Input::kMaxSteer);
    EXPECT_EQ(input_of({false, false, true, false}).steer, Input::kMaxSteer);
    EXPECT_EQ(input_of({false, true, true, false}).steer, 0);
    const Input brake = input_of({false, false, false, true});
    EXPECT_EQ(brake.brake, 1);
    EXPECT_EQ(brake.throttle, 0);
}

}  // namespace
}  // namespace jetrace::view

#include "tools/hostsim/fidelity.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace ddmr::hostsim {
namespace {

TEST(Fidelity, NoneAndAll) {
    EXPECT_TRUE(Fidelity::none().is_none());
    EXPECT_EQ(Fidelity::none().to_string(), "none");
    const Fidelity all = Fidelity::all();
    EXPECT_TRUE(all.is_all());
    EXPECT_EQ(all.names().size(), kFidelitySwitchCount);
    for (std::size_t k = 0; k < kFidelitySwitchCount; ++k) {
        EXPECT_TRUE(all.has(static_cast<FidelitySwitch>(k)));
    }
}

TEST(Fidelity, NamesFollowTheEnum) {
    EXPECT_STREQ(to_string(FidelitySwitch::int_gains), "int_gains");
    EXPECT_STREQ(to_string(FidelitySwitch::float32), "float32");
    EXPECT_STREQ(to_string(FidelitySwitch::encoder_odometry), "encoder_odometry");
    EXPECT_STREQ(to_string(FidelitySwitch::loop_period), "loop_period");
    EXPECT_STREQ(to_string(FidelitySwitch::feedforward_constants), "feedforward_constants");
    EXPECT_STREQ(to_string(FidelitySwitch::pwm_quantisation), "pwm_quantisation");
    EXPECT_STREQ(to_string(FidelitySwitch::eeprom_bytes), "eeprom_bytes");
}

TEST(Fidelity, ParsesAListInAnyOrderIntoCanonicalOrder) {
    const Fidelity f = Fidelity::parse("loop_period, int_gains,int_gains");
    EXPECT_TRUE(f.has(FidelitySwitch::int_gains));
    EXPECT_TRUE(f.has(FidelitySwitch::loop_period));
    EXPECT_FALSE(f.has(FidelitySwitch::float32));
    EXPECT_EQ(f.to_string(), "int_gains,loop_period");
    EXPECT_EQ(Fidelity::parse(f.to_string()), f);  // round trip
    EXPECT_EQ(Fidelity::parse("all"), Fidelity::all());
    EXPECT_EQ(Fidelity::parse("none"), Fidelity::none());
    EXPECT_EQ(Fidelity::parse(""), Fidelity::none());
}

TEST(Fidelity, RejectsAnUnknownSwitchNamingIt) {
    try {
        Fidelity::parse("int_gains,float64");
        FAIL() << "accepted float64";
    } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("'float64'"), std::string::npos) << what;
        EXPECT_NE(what.find("float32"), std::string::npos) << "should list the known names: " << what;
    }
    EXPECT_THROW(Fidelity::parse("int_gains,,float32"), std::invalid_argument);
    EXPECT_THROW(Fidelity::parse("int_gains,"), std::invalid_argument);
}

}  // namespace
}  // namespace ddmr::hostsim

#pragma once
// The reference sketch's constants (../shared/reference/ddmr_tracking.ino) as
// they compile for the ATmega328P, in one place. avr-gcc's `double` is 32-bit,
// so every literal below is a float on the robot; `int` is 16-bit.
//
// Each constant names the sketch line it mirrors. The host simulation uses
// them only when a fidelity switch asks for the firmware's behaviour
// (fidelity.hpp); the ideal model uses the plant's own parameters.

namespace ddmr::hostsim::firmware {

// --- loop timing ------------------------------------------------------------
/// `float dt=0.01;` the loop period the sketch assumes [s]; its clock `t`
/// and `Angref` advance by dt per iteration whatever the real period is.
inline constexpr double kDt_s = 0.01;
/// `delay(9)` plus ~1.1 ms of computing and, in case 1, EEPROM waits: the
/// period measured on the HIL [s]. Only documentation: --period-ms sets it.
inline constexpr double kMeasuredPeriod_s = 0.01044;
/// `k=10;` iterations between two EEPROM log writes (case 1).
inline constexpr int kIterationsPerLog = 10;

// --- odometry (`phi1dot=(phi1-phi1old)*radpuls*Gd;` ... `Ey=Ey + dt*sin(Theta)*Vel;`)
/// `const float radpuls=0.016362;` wheel angle per encoder edge [rad]
/// (2 pi / 384 = 0.0163625: 8 edges per motor turn, gear 48).
inline constexpr double kRadPerEdge = 0.016362;
/// `const float r1=0.03215;` wheel radius [m] (Table 2 says 32.2 mm).
inline constexpr double kWheelRadius_m = 0.03215;
/// `const float R=7.874;` 1 / (2 L) [1/m], L = 63.5 mm (Table 2: 64 mm).
inline constexpr double kInverseTrack_per_m = 7.874;

// --- control law (`v=vref*cos(etheta)+kx*errxr;` `w=wref+vref*(ky*erryr+kw*sin(etheta));`)
/// `const int kx=1.1;` as written; it compiles to 1 (int_gains).
inline constexpr double kKxAsWritten = 1.1;
inline constexpr double kKy = 6.0;         ///< `const int ky=6;`
inline constexpr double kKw = 8.0;         ///< `const int kw=8;`
inline constexpr double kVref_m_s = 0.2;   ///< `const float vref=0.2;` feed-forward v_g [m/s]
inline constexpr double kWref_rad_s = 0.2; ///< `const float wref=0.2;` feed-forward w_g [rad/s]

// --- feed-forward, eq. (17) (`Vdc1=int(255.0*GR*Ka*(30.3*v+1.92*w)*Batt);`)
inline constexpr double kPwmFullScale = 255.0;  ///< `255.0*...`: analogWrite's full scale
inline constexpr double kGearRatio = 48.0;      ///< `const int GR=48;`
inline constexpr double kKa_V_s_per_rad = 0.0054;  ///< `const float Ka=0.0054;` (the plant fits 0.00384)
inline constexpr double kInverseBattery_per_V = 0.164;  ///< `const float Batt=0.164;` 1 / 6.1 V
/// `30.3*v`: 1 / r with r = 0.033 m [1/m] (not the odometry's r1).
inline constexpr double kSpeedToWheel_per_m = 30.3;
/// `1.92*w`: L / r = 0.0635 / 0.033 [1].
inline constexpr double kTurnToWheel = 1.92;
/// analogWrite's largest duty value; `if (Vdc1>255) Vdc1=255;`
inline constexpr int kMaxDutyValue = 255;

// --- the two cases (`case '1':` / `case '2':`)
inline constexpr double kInitialHeading_rad = 1.571;  ///< `float Angref=1.571;`
inline constexpr double kCase1Radius_m = 0.6;         ///< `errx=0.6*cos(0.5236*t)-Ex;`
inline constexpr double kCase1Rate_rad_s = 0.5236;    ///< 2 pi / 12 s, as written
inline constexpr double kCase1Duration_s = 12.0;      ///< `NUM=1200;` x dt
inline constexpr double kCase2Radius_m = 0.4;         ///< `errx=0.4*cos(0.7854*t)-Ex;`
inline constexpr double kCase2Rate_rad_s = 0.7854;    ///< 2 pi / 8 s, as written
inline constexpr double kCase2Duration_s = 8.0;       ///< `NUM=800;` x dt

// --- EEPROM log (case 1: `EEPROM.write(addr,int(Ex*250.0));`)
inline constexpr double kLogCountsPerMetre = 250.0;
/// x bytes at 0, 2, ..., 498 and y bytes 500 above them: at most 250 samples
/// before the x bytes would run into the y bytes.
inline constexpr int kLogMaxSamples = 250;

}  // namespace ddmr::hostsim::firmware

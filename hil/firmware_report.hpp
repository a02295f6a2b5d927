#pragma once
// The reference sketch's serial output, parsed: the case banner ("0.6m" or
// "0.4m") and the end-of-run report that follows "END":
//
//   Count1                      unsigned long
//   Count2                      unsigned long
//   Gx,<f3>,Gy,<f3>,t,<f3>      goal point and time at the end
//   pdt1,<f2>,pdt2,<f2>         last wheel-speed estimates
//   V,<f4>,W,<f4>               last body velocities
//   Ex,<f4>,Ey,<f4>,Thta,<f4>   end pose estimate
//   ex,<f4>,ey,<f4>,exr,<f4>    end tracking errors
//   addr                        (case 1 only) EEPROM bytes used per axis
//   <x> , <y>                   (case 1 only) addr/2 + 1 logged points, decoded
//
// Numbers are kept as double; Arduino prints "nan", "inf" and "ovf", which
// become NaN / +-inf (JSON null) so a broken run is visible, not hidden.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ddmr::hil {

struct FirmwareReport {
    std::string banner;  ///< "0.6m" or "0.4m"
    bool ended = false;  ///< "END" was seen
    std::optional<double> count1, count2;
    std::optional<double> gx, gy, t;
    std::optional<double> pdt1, pdt2;
    std::optional<double> v, w;
    std::optional<double> ex, ey, theta;
    std::optional<double> errx, erry, errxr;
    std::optional<double> addr;
    std::vector<std::pair<double, double>> eeprom_pairs;  ///< (x, y) in metres
};

class FirmwareReportParser {
public:
    /// `expects_eeprom_dump`: the report ends with `addr` and the EEPROM pairs
    /// (case 1 of the reference sketch); otherwise it ends with the "ex," line.
    explicit FirmwareReportParser(bool expects_eeprom_dump)
        : expects_eeprom_dump_(expects_eeprom_dump) {}

    /// Feeds bytes as the firmware sent them.
    void feed(std::string_view bytes);
    /// The whole report has been received.
    bool complete() const { return stage_ == Stage::kComplete; }
    /// A line did not have the expected form; the message names it.
    const std::optional<std::string>& error() const { return error_; }
    const FirmwareReport& report() const { return report_; }

private:
    enum class Stage {
        kBanner, kEnd, kCount1, kCount2, kGoal, kPdt, kVel, kPose, kErr, kAddr, kPairs, kComplete
    };
    void on_line(const std::string& line);
    void fail(const std::string& line, const char* expected);

    bool expects_eeprom_dump_;
    Stage stage_ = Stage::kBanner;
    std::string partial_;
    std::size_t line_number_ = 0;
    std::size_t pairs_expected_ = 0;
    std::optional<std::string> error_;
    FirmwareReport report_;
};

}  // namespace ddmr::hil

#include "calibrate/identifiability.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace ddmr::calibrate {
namespace {

/// An interval wider than this factor either way does not pin the parameter.
constexpr double kMaxIntervalFactor = 2.0;
/// The change used to say "the log does not depend on it" [relative].
constexpr double kProbeChange = 0.10;
constexpr double kZ95 = 1.959963984540054;

}  // namespace

double log_noise_m() { return 0.004 / std::sqrt(12.0); }

Identifiability analyse_identifiability(const std::function<std::vector<double>(const std::vector<double>&)>& predict,
                                        const std::vector<std::string>& keys, const std::vector<double>& at,
                                        double sigma_m, double relative_step) {
    const auto n = static_cast<Eigen::Index>(at.size());
    if (keys.size() != at.size() || at.empty()) throw std::invalid_argument("identifiability: one key per value, at least one");
    if (!(sigma_m > 0.0)) throw std::invalid_argument("identifiability: sigma must be > 0");
    if (!(relative_step > 0.0 && relative_step <= 0.5)) throw std::invalid_argument("identifiability: step must be in (0, 0.5]");
    for (std::size_t j = 0; j < at.size(); ++j) {
        if (!(at[j] > 0.0 && std::isfinite(at[j]))) {
            throw std::invalid_argument(fmt::format("identifiability: {} = {} is not a positive value", keys[j], at[j]));
        }
    }
    // S: d y / d ln(theta), central differences.
    Eigen::MatrixXd s;
    for (Eigen::Index j = 0; j < n; ++j) {
        std::vector<double> up = at;
        std::vector<double> down = at;
        up[static_cast<std::size_t>(j)] *= std::exp(relative_step);
        down[static_cast<std::size_t>(j)] *= std::exp(-relative_step);
        const std::vector<double> yu = predict(up);
        const std::vector<double> yd = predict(down);
        if (yu.size() != yd.size() || yu.empty()) throw std::runtime_error("identifiability: the prediction changed size");
        if (j == 0) s.resize(static_cast<Eigen::Index>(yu.size()), n);
        if (static_cast<Eigen::Index>(yu.size()) != s.rows()) throw std::runtime_error("identifiability: the prediction changed size");
        for (Eigen::Index i = 0; i < s.rows(); ++i) {
            s(i, j) = (yu[static_cast<std::size_t>(i)] - yd[static_cast<std::size_t>(i)]) / (2.0 * relative_step);
        }
    }
    Identifiability out;
    out.sigma_m = sigma_m;
    const Eigen::MatrixXd scaled = s / sigma_m;
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(scaled);
    for (Eigen::Index k = 0; k < svd.singularValues().size(); ++k) out.singular_values.push_back(svd.singularValues()(k));
    // The parameters the log does depend on: their covariance alone (one the
    // log ignores would make every other look unidentifiable too).
    std::vector<Eigen::Index> seen;
    for (Eigen::Index j = 0; j < n; ++j) {
        if (scaled.col(j).norm() * std::log1p(kProbeChange) >= 1.0) seen.push_back(j);
    }
    const auto m = static_cast<Eigen::Index>(seen.size());
    Eigen::MatrixXd sub(scaled.rows(), m);
    for (Eigen::Index k = 0; k < m; ++k) sub.col(k) = scaled.col(seen[static_cast<std::size_t>(k)]);
    const Eigen::MatrixXd fisher = sub.transpose() * sub;
    const Eigen::JacobiSVD<Eigen::MatrixXd> sub_svd(sub);
    const bool invertible = m > 0 && sub_svd.singularValues()(m - 1) > 1e-9 * sub_svd.singularValues()(0);
    const Eigen::MatrixXd sub_cov = invertible ? Eigen::MatrixXd(fisher.inverse()) : Eigen::MatrixXd();
    // Full-size covariance and correlation (NaN where a parameter is not seen or F is singular).
    const double nan = std::numeric_limits<double>::quiet_NaN();
    Eigen::MatrixXd cov = Eigen::MatrixXd::Constant(n, n, nan);
    if (invertible) {
        for (Eigen::Index a = 0; a < m; ++a) {
            for (Eigen::Index b = 0; b < m; ++b) cov(seen[static_cast<std::size_t>(a)], seen[static_cast<std::size_t>(b)]) = sub_cov(a, b);
        }
    }
    out.correlation = Eigen::MatrixXd::Constant(n, n, nan);
    for (Eigen::Index a = 0; a < n; ++a) {
        for (Eigen::Index b = 0; b < n; ++b) out.correlation(a, b) = cov(a, b) / std::sqrt(cov(a, a) * cov(b, b));
    }
    const double rows = static_cast<double>(s.rows());
    for (Eigen::Index j = 0; j < n; ++j) {
        ParamIdentifiability p;
        p.key = keys[static_cast<std::size_t>(j)];
        p.value = at[static_cast<std::size_t>(j)];
        // RMS change of the log for a +10 % change (linearised).
        p.sensitivity_m = s.col(j).norm() * std::log1p(kProbeChange) / std::sqrt(rows);
        p.relative_sd = std::isfinite(cov(j, j)) ? std::sqrt(cov(j, j)) : std::numeric_limits<double>::infinity();
        p.ci_lo = p.value;
        p.ci_hi = p.value;
        const bool is_seen = std::find(seen.begin(), seen.end(), j) != seen.end();
        if (!is_seen) {
            p.identifiable = false;
            p.reason = fmt::format("the log does not depend on it: a 10 % change moves the logged track by {:.2g} mm "
                                   "RMS, less than one quantisation sigma ({:.2g} mm) over the whole log",
                                   p.sensitivity_m * 1e3, sigma_m * 1e3);
        } else if (!std::isfinite(p.relative_sd) || std::exp(kZ95 * p.relative_sd) > kMaxIntervalFactor) {
            // The seen parameter it trades off with most.
            Eigen::Index partner = j;
            double strongest = -1.0;
            for (const Eigen::Index k : seen) {
                if (k == j) continue;
                const double c = invertible ? std::fabs(out.correlation(j, k))
                                            : std::fabs(scaled.col(j).normalized().dot(scaled.col(k).normalized()));
                if (c > strongest) {
                    strongest = c;
                    partner = k;
                }
            }
            p.identifiable = false;
            p.reason = partner == j
                           ? fmt::format("the log cannot pin it: its 95 % interval spans more than a factor of {}",
                                         kMaxIntervalFactor)
                           : fmt::format("the log cannot separate it from {} (correlation {:.3f}): only a combination "
                                         "of the two is seen",
                                         keys[static_cast<std::size_t>(partner)],
                                         invertible ? out.correlation(j, partner) : strongest);
        }
        if (std::isfinite(p.relative_sd)) {
            p.ci_lo = p.value * std::exp(-kZ95 * p.relative_sd);
            p.ci_hi = p.value * std::exp(kZ95 * p.relative_sd);
        }
        out.params.push_back(p);
    }
    return out;
}

}  // namespace ddmr::calibrate

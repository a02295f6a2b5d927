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
/// A singular value below this fraction of the largest is a direction the log does not see.
constexpr double kNullRatio = 1e-6;
/// A parameter whose weight in such a direction exceeds this is not identifiable.
constexpr double kNullWeight = 0.1;


void check_point(const std::vector<std::string>& keys, const std::vector<double>& at) {
    if (keys.size() != at.size() || at.empty()) throw std::invalid_argument("identifiability: one key per value, at least one");
    for (std::size_t j = 0; j < at.size(); ++j) {
        if (!(at[j] > 0.0 && std::isfinite(at[j]))) {
            throw std::invalid_argument(fmt::format("identifiability: {} = {} is not a positive value", keys[j], at[j]));
        }
    }
}

}  // namespace

double log_noise_m() { return 0.004 / std::sqrt(12.0); }

Eigen::MatrixXd sensitivity_matrix(const std::function<std::vector<double>(const std::vector<double>&)>& predict,
                                   const std::vector<double>& at, double relative_step) {
    if (!(relative_step > 0.0 && relative_step <= 0.5)) throw std::invalid_argument("identifiability: step must be in (0, 0.5]");
    const auto n = static_cast<Eigen::Index>(at.size());
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
    return s;
}

Identifiability analyse_identifiability(const std::function<std::vector<double>(const std::vector<double>&)>& predict,
                                        const std::vector<std::string>& keys, const std::vector<double>& at,
                                        double sigma_m, double relative_step, double model_tolerance_m) {
    check_point(keys, at);
    if (!(sigma_m > 0.0)) throw std::invalid_argument("identifiability: sigma must be > 0");
    return analyse_sensitivities(sensitivity_matrix(predict, at, relative_step), keys, at, sigma_m, model_tolerance_m);
}

Identifiability analyse_sensitivities(const Eigen::MatrixXd& s, const std::vector<std::string>& keys,
                                      const std::vector<double>& at, double sigma_m, double model_tolerance_m) {
    check_point(keys, at);
    if (!(sigma_m > 0.0)) throw std::invalid_argument("identifiability: sigma must be > 0");
    if (!(model_tolerance_m >= 0.0)) throw std::invalid_argument("identifiability: the model tolerance must be >= 0");
    const auto n = static_cast<Eigen::Index>(at.size());
    if (s.cols() != n || s.rows() == 0) throw std::invalid_argument("identifiability: one sensitivity column per parameter");
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
    // The covariance of ln(theta) over the seen parameters from the SVD of
    // sub = U diag(s) V^T: F = V diag(s^2) V^T, C = V diag(1 / s^2) V^T over
    // the directions the log sees (s_k > kNullRatio s_0). A direction below
    // that (or missing: fewer log values than parameters) is one the log
    // cannot see; a parameter with weight in it is not identifiable.
    Eigen::MatrixXd v;
    Eigen::VectorXd sv;
    if (m > 0) {
        const Eigen::JacobiSVD<Eigen::MatrixXd> sub_svd(sub, Eigen::ComputeFullV);
        v = sub_svd.matrixV();
        sv = Eigen::VectorXd::Zero(m);
        sv.head(sub_svd.singularValues().size()) = sub_svd.singularValues();
    }
    std::vector<bool> null_direction(static_cast<std::size_t>(m), false);
    for (Eigen::Index k = 0; k < m; ++k) null_direction[static_cast<std::size_t>(k)] = !(sv(k) > kNullRatio * sv(0));
    const double nan = std::numeric_limits<double>::quiet_NaN();
    Eigen::MatrixXd cov = Eigen::MatrixXd::Constant(n, n, nan);
    for (Eigen::Index a = 0; a < m; ++a) {
        for (Eigen::Index b = 0; b < m; ++b) {
            double c = 0.0;
            for (Eigen::Index k = 0; k < m; ++k) {
                if (!null_direction[static_cast<std::size_t>(k)]) c += v(a, k) * v(b, k) / (sv(k) * sv(k));
            }
            cov(seen[static_cast<std::size_t>(a)], seen[static_cast<std::size_t>(b)]) = c;
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
        p.ci_lo = p.value;
        p.ci_hi = p.value;
        p.relative_sd = std::numeric_limits<double>::infinity();
        p.half_width = std::numeric_limits<double>::infinity();
        const auto at_seen = std::find(seen.begin(), seen.end(), j);
        if (at_seen == seen.end()) {
            p.identifiable = false;
            p.reason = fmt::format("the log does not depend on it: a 10 % change moves the whole logged track by "
                                   "{:.2g} mm (root sum of squares over its {} values), less than one quantisation "
                                   "sigma ({:.2g} mm)",
                                   s.col(j).norm() * std::log1p(kProbeChange) * 1e3, s.rows(), sigma_m * 1e3);
            out.params.push_back(p);
            continue;
        }
        const auto a = static_cast<Eigen::Index>(at_seen - seen.begin());
        // Its weight in a direction the log cannot see, and the seen parameter weighing most there with it.
        Eigen::Index partner = -1;
        double partner_weight = 0.0;
        double null_weight = 0.0;
        for (Eigen::Index k = 0; k < m; ++k) {
            if (!null_direction[static_cast<std::size_t>(k)] || std::fabs(v(a, k)) <= kNullWeight) continue;
            null_weight = std::max(null_weight, std::fabs(v(a, k)));
            for (Eigen::Index b = 0; b < m; ++b) {
                if (b != a && std::fabs(v(b, k)) > partner_weight) {
                    partner_weight = std::fabs(v(b, k));
                    partner = seen[static_cast<std::size_t>(b)];
                }
            }
        }
        if (null_weight == 0.0) {
            p.relative_sd = std::sqrt(cov(j, j));
            // The model's tolerance: the change of ln(theta) (the others
            // re-fitted) that moves the track by model_tolerance_m RMS over
            // its values: dRMS^2 = d^2 / (rows x (S^T S)^-1_jj).
            p.half_width = std::max(kZ95 * p.relative_sd, model_tolerance_m * std::sqrt(rows) * p.relative_sd / sigma_m);
        }
        if (null_weight > 0.0 || std::exp(p.half_width) > kMaxIntervalFactor) {
            if (null_weight == 0.0) {
                // Pinned badly rather than not at all: the parameter it is most correlated with.
                for (const Eigen::Index k : seen) {
                    if (k != j && std::fabs(out.correlation(j, k)) > partner_weight) {
                        partner_weight = std::fabs(out.correlation(j, k));
                        partner = k;
                    }
                }
            }
            p.identifiable = false;
            if (partner < 0) {
                p.reason = fmt::format("the log cannot pin it: its 95 % interval spans more than a factor of {}",
                                       kMaxIntervalFactor);
            } else if (null_weight > 0.0) {
                p.reason = fmt::format("the log cannot separate it from {}: only a combination of the two is seen "
                                       "(a direction of parameter space the log does not see)",
                                       keys[static_cast<std::size_t>(partner)]);
            } else {
                p.reason = fmt::format("the log cannot separate it from {} (correlation {:.3f}): its 95 % interval "
                                       "spans more than a factor of {}",
                                       keys[static_cast<std::size_t>(partner)], out.correlation(j, partner),
                                       kMaxIntervalFactor);
            }
        }
        if (std::isfinite(p.half_width)) {
            p.ci_lo = p.value * std::exp(-p.half_width);
            p.ci_hi = p.value * std::exp(p.half_width);
        }
        out.params.push_back(p);
    }
    return out;
}

Selection select_identifiable(const Eigen::MatrixXd& s, const std::vector<std::string>& keys,
                              const std::vector<double>& at, double max_half_width, double sigma_m,
                              double model_tolerance_m) {
    check_point(keys, at);
    if (s.cols() != static_cast<Eigen::Index>(keys.size())) {
        throw std::invalid_argument("identifiability: one sensitivity column per parameter");
    }
    if (!(max_half_width > 0.0)) throw std::invalid_argument("identifiability: the largest half-width must be > 0");
    // Most visible first; ties in file order (a stable sort: deterministic).
    std::vector<std::size_t> order(keys.size());
    for (std::size_t j = 0; j < order.size(); ++j) order[j] = j;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return s.col(static_cast<Eigen::Index>(a)).norm() > s.col(static_cast<Eigen::Index>(b)).norm();
    });
    Selection out;
    for (const std::size_t j : order) {
        std::vector<std::size_t> trial = out.chosen;
        trial.push_back(j);
        Eigen::MatrixXd sub(s.rows(), static_cast<Eigen::Index>(trial.size()));
        std::vector<std::string> sub_keys;
        std::vector<double> sub_at;
        for (std::size_t k = 0; k < trial.size(); ++k) {
            sub.col(static_cast<Eigen::Index>(k)) = s.col(static_cast<Eigen::Index>(trial[k]));
            sub_keys.push_back(keys[trial[k]]);
            sub_at.push_back(at[trial[k]]);
        }
        const Identifiability a = analyse_sensitivities(sub, sub_keys, sub_at, sigma_m, model_tolerance_m);
        const ParamIdentifiability& mine = a.params.back();
        std::string reason;
        if (!mine.identifiable) {
            reason = mine.reason;
        } else if (mine.half_width > max_half_width) {
            reason = fmt::format("the log pins it only to within x{:.2f} either way", std::exp(mine.half_width));
        } else {
            // Adding it must not spoil one chosen before.
            for (std::size_t k = 0; k + 1 < trial.size() && reason.empty(); ++k) {
                const ParamIdentifiability& other = a.params[k];
                if (!other.identifiable || other.half_width > max_half_width) {
                    reason = fmt::format("the log cannot separate it from {}, fitted before it (more visible)", other.key);
                }
            }
        }
        if (reason.empty()) {
            out.chosen.push_back(j);
        } else {
            out.left_out.push_back({j, reason});
        }
    }
    std::sort(out.chosen.begin(), out.chosen.end());
    return out;
}

}  // namespace ddmr::calibrate

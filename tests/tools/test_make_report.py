"""The data the run report plots (tools/report/make_report.py), worked out by
hand: the PWM-window statistics that replace aliased 1 kHz samples."""
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "tools", "report"))

import make_report  # noqa: E402


def test_the_pwm_period_is_the_unos_490_hz():
    # Timer1/2 phase-correct 8-bit, prescaler 64: 16 MHz / (64 x 510) = 490.196 Hz.
    assert math.isclose(1.0 / make_report.PWM_PERIOD_S, 490.196, rel_tol=1e-5)


def test_a_pwm_square_wave_sampled_at_1khz_averages_to_its_duty():
    # A 490 Hz wave at duty 0.3 between 0 and 2 A, sampled at 1 kHz for 2 s:
    # each sample alone is 0 or 2 (the solid blocks). A window of 25 PWM
    # periods (51 ms) holds 51 or 52 samples at evenly spread phases of the
    # cycle, 15 to 17 of them high: its mean is the wave's (0.6 A) within
    # 0.06 (2 A x 3/104: a sample more or less at each end). The envelope
    # spans 0..2 A.
    p = make_report.PWM_PERIOD_S
    t = [k * 1e-3 for k in range(2000)]
    y = [2.0 if (tk / p) % 1.0 < 0.3 else 0.0 for tk in t]
    window = make_report.WINDOW_PERIODS * p
    stats = make_report.window_stats(t, y, window)
    assert len(stats) == int(t[-1] / window)  # whole windows only: 39
    for centre, mean, lo, hi in stats:
        assert abs(mean - 0.6) <= 0.06, (centre, mean)
        assert (lo, hi) == (0.0, 2.0)
    # A window of 10 periods (20.4 ms) sees 2/5 of a beat: its mean is off by up to 0.5 A.
    short = make_report.window_stats(t, y, 10 * p)
    assert max(abs(s[1] - 0.6) for s in short) > 0.3


def test_a_constant_stays_constant_and_windows_are_centred():
    t = [k * 1e-3 for k in range(100)]
    stats = make_report.window_stats(t, [5.0] * 100, 0.02)
    assert [s[1:] for s in stats] == [(5.0, 5.0, 5.0)] * 4  # 0-20, ..., 60-80 ms; 80-100 ms is partial
    assert [round(s[0], 6) for s in stats] == [0.01, 0.03, 0.05, 0.07]
    assert make_report.window_stats([], [], 0.02) == []

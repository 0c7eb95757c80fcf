"""What `run` prints of one run: a real-time run's own factor of real time (issue 48: an external
SUT's run showed `(0x real time)`)."""
from harness.campaign.adhoc import summary
from harness.textable import real_time_factor
from harness.trace import Trace


def test_a_real_time_run_shows_its_own_factor_of_real_time():
    trace = Trace("ros2-node", 1, sim_s=21.0, wall_s=35.0)  # startup and teardown cost wall time
    assert "simulated 21.0 s, wall 35.000 s (0.6x real time)" in summary(trace, {})


def test_the_factor_keeps_two_figures_below_ten_and_none_above():
    assert [real_time_factor(s, 10.0) for s in (1.3, 9.94, 12.0, 98765.0)] == ["0.13x", "0.99x", "1.2x",
                                                                               "9,876x"]
    assert real_time_factor(5.0, 0.0) == "-"

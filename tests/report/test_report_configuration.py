"""The configuration the report shows of a campaign is what its strategy used (issue 48: a focused
campaign showed `mutants = 300`, which it never used)."""
from harness.report.configuration import shown

FOCUSED = {"strategy": "focused", "mutants": 300, "ops_per_mutant": 1, "operators": None,
           "time_mutations": False, "shard": None, "seed": 2012, "budget_s": 4000.0, "sut": ["genom"]}


def test_a_focused_campaign_shows_its_tests_and_why_it_stopped_not_the_random_strategy_s_flags():
    config = shown(FOCUSED, {"tests": 88, "stopped": "rule"})
    assert config == {"strategy": "focused", "seed": 2012, "budget_s": 4000.0, "sut": ["genom"],
                      "tests": 88, "stopped": "rule"}


def test_the_cap_on_a_focused_campaign_s_tests_is_shown_where_it_stopped_it():
    config = shown(FOCUSED, {"tests": 300, "stopped": "tests"})
    assert config["tests at most (--mutants)"] == 300 and "mutants" not in config


def test_an_unfinished_focused_campaign_says_so():
    assert shown(FOCUSED, {"tests": 16, "stopped": None})["stopped"].startswith("not yet")
    assert "tests" not in shown(FOCUSED, None) and "mutants" not in shown(FOCUSED, None)


def test_a_random_campaign_shows_its_whole_configuration():
    random = dict(FOCUSED, strategy="random", budget_s=None)
    assert shown(random, None) == random

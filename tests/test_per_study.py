"""contracts.work.PerStudy: what a study's parts share is made once per study in a process, and made again for the
next study (a worker flies one run at a time)."""

from footprint.contracts.work import PerStudy


def test_a_plan_is_made_once_per_study_and_again_for_the_next():
    made = []
    plan = PerStudy(lambda study: made.append(study) or f"plan of {study['name']}")
    first, second = {"name": "a"}, {"name": "a"}  # equal, but another request
    assert plan(first) == plan(first) == "plan of a" and made == [first]
    assert plan(second) == "plan of a" and made == [first, second]
    assert plan(first) == "plan of a" and len(made) == 3  # one kept: the first is made again

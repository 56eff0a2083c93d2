"""evaluation/cost.py: the running-cost budget of issue 30 judged on the worst default run."""
from blind_navigation.evaluation import cost


def run(recording, returning, rss):
    return {'layer_recording': recording, 'layer_returning': returning, 'layer_hwm_mb': rss}


def test_budget_met_only_when_every_default_run_is_within_it():
    assert cost._verdict('default', [run(2.3, 7.1, 55.3), run(2.5, 7.6, 55.0)]).count('met') == 3
    verdict = cost._verdict('default', [run(2.3, 7.1, 55.3), run(5.2, 7.6, 55.0)])
    assert 'recording <= 5 %: MISSED (5.20)' in verdict
    assert 'RSS <= 114.4 MiB: MISSED' in cost._verdict('default', [run(2.0, 6.0, 115.0)])


def test_no_budget_for_other_layouts_and_unmeasured_phases_are_said():
    assert cost._verdict('paper', [run(20.0, 30.0, 350.0)]) == '(no budget)'
    assert 'returning: not measured' in cost._verdict('default', [run(2.0, None, 50.0)])


def test_cpu_model_names_the_model_and_cores(tmp_path):
    info = tmp_path / 'cpuinfo'
    info.write_text('processor\t: 0\nmodel name\t: Test CPU\n\nprocessor\t: 1\nmodel name\t: Test CPU\n')
    assert cost.cpu_model(str(info)) == 'Test CPU, 2 cores'
    assert cost.cpu_model(str(tmp_path / 'missing')) == 'unknown CPU'

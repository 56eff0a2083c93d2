"""Recovery survival (issue 23): bench_probe's cases on bench.launch over seeds.

``brief``: vision lost ``loss`` s mid-mission, survived if back to ``recording`` with no
return, then ``go_home``; ``bump``: the bumper pressed ``press`` s into ``returning``,
survived if still ``home`` (docs/evaluation.md, "Recovery survival").
"""
import os

from .report import markdown_table, med_worst, num, write_csv

CASES = ('brief', 'bump')
MISSION = 'test_left_arc'
#: sim s: the loss's start after the first command and its length; the bump's start after
#: the return started and its length (the issue's numbers).
FAIL_AFTER, LOSS, PRESS_AFTER, PRESS = 5.0, 3.0, 5.0, 1.0


def bumper_event(publisher, pressed):
    """Publish the center bumper ``pressed`` (or released) on ``publisher``."""
    from blind_navigation.ros import kobuki_msgs_compat as kobuki
    publisher.publish(kobuki.BumperEvent(bumper=kobuki.BumperEvent.CENTER, state=kobuki.BumperEvent.PRESSED
                                         if pressed else kobuki.BumperEvent.RELEASED))


def press_bumper(publisher, seconds, sleep):
    """Press the center bumper on ``publisher`` for ``seconds`` (``sleep``: sim-time sleep)."""
    bumper_event(publisher, True)
    sleep(seconds)
    bumper_event(publisher, False)


def chatter_bumper(publisher, seconds, rate, now, until):
    """Press and release the center bumper on ``publisher`` ``rate`` times a second for
    ``seconds``, pressed half of each period, on a schedule of sim times from the first
    press (``now()``: sim time; ``until(t)``: waits until sim time ``t``). Returns the
    sim times of the presses."""
    start, presses = now(), []
    for k in range(int(round(seconds * rate))):
        until(start + k / rate)
        presses.append(now())
        bumper_event(publisher, True)
        until(start + (k + 0.5) / rate)
        bumper_event(publisher, False)
    return presses


def run_case(probe, set_vision):
    """Drive ``probe`` (a BenchProbe after ``recording``) through its case; returns the
    case's findings (merged into its JSON)."""
    import rospy
    from std_srvs.srv import Trigger
    from blind_navigation import names
    from blind_navigation.core.mission_state import TERMINAL
    p = probe.params
    if p.case == 'brief':
        probe.wait(lambda: 'mission_start' in probe.times, 600.0, 'the mission to start')
        probe.wait(lambda: rospy.Time.now().to_sec() >= probe.times['mission_start'] + FAIL_AFTER,
                   60.0, 'the mission under way')
        set_vision(False)
        rospy.sleep(LOSS)
        set_vision(True)
        probe.wait(lambda: probe.mission_done, 3600.0, 'the scripted mission to finish')
        rospy.sleep(p.settle)
        states = list(probe.states)
        survived = ('rotating' in states and states[-1] == 'recording'
                    and 'returning' not in states)
        go_home = rospy.ServiceProxy(names.GO_HOME, Trigger)
        go_home.wait_for_service(timeout=30.0)
        reply = go_home()
        found = {'survived': survived, 'before_go_home': states, 'go_home': reply.message}
    else:
        probe.wait(lambda: probe.mission_done, 3600.0, 'the scripted mission to finish')
        rospy.sleep(p.settle)
        set_vision(False)
        probe.wait(lambda: probe.state == 'returning', p.timeout, 'the return')
        rospy.sleep(PRESS_AFTER)
        from blind_navigation.ros import kobuki_msgs_compat as kobuki
        bumper = rospy.Publisher(names.SAFETY_EVENTS['bumper'], kobuki.BumperEvent, queue_size=5)
        probe.wait(lambda: bumper.get_num_connections() >= 1, 30.0, 'the layer to subscribe the bumper')
        speed_at_press = probe.speed
        press_bumper(bumper, PRESS, rospy.sleep)
        found = {'speed_at_press': speed_at_press, 'speed_at_release': probe.speed}
    probe.wait(lambda: probe.state in TERMINAL, p.timeout, 'state home or aborted')
    found['states'] = list(probe.states)
    if p.case == 'bump':
        found['survived'] = probe.state == 'home'
    return found


def section(out_dir, seeds, rtf, log):
    """Run both cases over ``seeds`` seeds on bench.launch; (Markdown text, rows)."""
    from .ros_runs import run_ros
    runs = []
    for case in CASES:
        for seed in range(seeds):
            log('recovery survival: %s seed %d (rtf %g)' % (case, seed, rtf))
            run = run_ros(os.path.join(out_dir, 'survival'), MISSION, 'closed_loop', seed, rtf,
                          bag=False, timeout=300.0, case=case)
            run['case'] = case
            runs.append(run)
    for r in runs:
        r['error_pct'] = 100.0 * r['error'] / r['length'] if r.get('length') else None
        r['contacts'] = logged_contacts(r['log'])
    write_csv(os.path.join(out_dir, 'survival.csv'), runs,
              ['case', 'seed', 'survived', 'state', 'length', 'error', 'error_pct', 'contacts', 'speed_at_release',
               'abort_reason', 'behind_real_time', 'wall_s', 'failed'])
    return table(runs, seeds, rtf), runs


def logged_contacts(log):
    """How many bumper contacts the back-travel server logged in the launch log ``log``."""
    with open(log, errors='replace') as stream:
        return sum(1 for line in stream if ': bumper contact ' in line)


def table(runs, seeds, rtf):
    lines = []
    for case in CASES:
        rows = [r for r in runs if r['case'] == case]
        survived = [r for r in rows if r.get('survived')]
        home = [r for r in survived if r.get('state') == 'home']
        felt = [r for r in rows if r.get('contacts')]
        lines.append([case, len(rows), '%d (%.0f %%)' % (len(survived), 100.0 * len(survived) / max(len(rows), 1)),
                      len(felt), med_worst([r.get('speed_at_release') for r in rows]), len(home), med_worst([r['error_pct'] for r in home], 2),
                      med_worst([r['error'] for r in home]),
                      ', '.join('%d%s' % (r['seed'], '' if r.get('survived') else ' (%s)' % (
                          r.get('failed') or r.get('abort_reason') or r.get('state')))
                          for r in rows)])
    return ('Mission %s on the fake TurtleBot (paper noise profile, closed_loop, default launch, no gyro '
            'calibration file), seeds 0..%d, rtf %g. brief: a %g s vision loss %g s (sim) after the first '
            'command, survived = back to `recording` without a return, then `go_home`; bump: the center '
            'bumper pressed %g s, %g s into the return, survived = still `home`; speed at the release: ground truth '
            '(the paper profile\'s motors lag 0.25 s). Error = ground truth '
            'start to end, %% of the recorded path.\n\n%s\n' % (
                MISSION, seeds - 1, rtf, LOSS, FAIL_AFTER, PRESS, PRESS_AFTER,
                markdown_table(['case', 'runs', 'survived', 'runs with a contact logged',
                                'speed at the release m/s median (max)', 'home', 'error % median (max)',
                                'error m median (max)', 'seeds (failures: why)'], lines)))

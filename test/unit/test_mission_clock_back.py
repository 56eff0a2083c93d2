"""The clock moving back while recording (a restarted simulator, issue 28 item 4): the
mission's recording goes on, its schedule counting from the new time (no tick waits for
the old one), and its gap names the reset."""
from blind_navigation.core.geometry import OdomState
from blind_navigation.core.mission import Inputs, Mission
from test_landmark_request import FileStore

SPEED, RATE, PERIOD = 0.1, 50, 2.0      # m/s, odometry Hz, the straight period (s)


def test_the_recording_goes_on_after_the_clock_moved_back(tmp_path):
    store = FileStore(str(tmp_path / 'landmarks.yaml'))
    mission = Mission(None, store, heading_correction=False, straight_period=PERIOD)
    taken = []

    def drive(start, end, x0, reset=None, time_back=None):
        for k in range(int(round((end - start) * RATE)) + 1):
            t = start + k / float(RATE)
            odom = OdomState(x0 + SPEED * (t - start), 0.0, 0.0, SPEED, 0.0, t)
            step = mission.step(t, Inputs(odom, reset=reset if k == 0 else None,
                                          time_back=time_back if k == 0 else None))
            taken.extend((t, lm) for lm in step.stored)

    drive(0.0, 9.0, 0.0)
    before = len(taken)
    # the simulator restarts: the clock from 0, the odometry from the origin (an untrusted reset)
    drive(0.02, 9.0, 0.0, reset='odometry reset not re-anchored (a restarted driver?)',
          time_back='the ROS time moved back 9.0 s')
    after = [t for t, _ in taken[before:]]
    assert mission.state == 'recording', mission.reason
    assert after and after[0] <= 0.02 + PERIOD + 1e-6, 'no landmark within a period of the new clock: %s' % after
    assert all(b - a <= PERIOD + 1e-6 for a, b in zip(after, after[1:])), after
    assert len(store.load().gaps) == 1

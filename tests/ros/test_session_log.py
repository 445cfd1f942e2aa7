import numpy as np
import pytest

pytest.importorskip("rosbags")
import comcore
from comcore.ros import TOPICS, SessionLog, read_session_log
from tests.extras import require_simulators


@pytest.fixture(scope="module")
def logged(tmp_path_factory):
    """Two pushes of a simulated object, logged step by step with a camera frame."""
    simulators = require_simulators()
    robot = simulators.SimulatedRobot(simulators.random_simulator("Obj2", "low", rng=0), rng=0)
    mask = robot.camera_mask()
    session = comcore.ActiveSession(mask, pusher_radius=0.004, rng=0,
                                    stop=comcore.StopRule(max_pushes=2))
    path = tmp_path_factory.mktemp("log") / "run"
    frames, masks, estimates = [], [], []
    with SessionLog(path) as log:
        for k in range(3):
            frame = (np.asarray(mask.data, np.uint8) * 200 + 20)[..., None].repeat(3, axis=2)
            log.step(session, mask=mask, frame=frame, time=10.0 + k)
            frames.append(frame), masks.append(mask), estimates.append(session.estimate())
            if session.done:
                break
            robot.execute(session.next_push())
            mask = robot.camera_mask()
            session.observe(mask)
    return path, session, frames, masks, estimates


def test_a_logged_session_reads_back_step_by_step(logged):
    path, session, frames, masks, estimates = logged
    steps = read_session_log(path)
    assert len(steps) == len(estimates) == 3
    for step, frame, mask, est in zip(steps, frames, masks, estimates):
        assert set(step) >= {"time", "camera", "mask", "posterior", "region", "pushes",
                             "estimate", "status"}
        np.testing.assert_array_equal(step["camera"], frame)
        np.testing.assert_array_equal(step["mask"] > 0, mask.data)
        np.testing.assert_array_equal(step["region"] > 0, est.region)
        np.testing.assert_allclose(step["estimate"], est.com_m)
        assert step["status"]["status"] == str(est.status)
        assert step["posterior"].max() == 255
    assert [s["time"] for s in steps] == [10.0, 11.0, 12.0]
    # the pushes so far, in the first mask's metres
    res = masks[0].resolution
    np.testing.assert_allclose(steps[-1]["pushes"], np.asarray(session.actions) * res)
    assert len(steps[0]["pushes"]) == 0 and len(steps[-1]["pushes"]) == 2


def test_every_topic_is_a_standard_ros2_message_in_an_mcap_file(logged):
    path = logged[0]
    from rosbags.rosbag2 import Reader

    assert len(list(path.glob("*.mcap"))) == 1
    with Reader(path) as reader:
        kinds = {c.topic: c.msgtype for c in reader.connections}
    assert kinds == TOPICS


def test_a_log_refuses_what_it_cannot_write(tmp_path, square_mask):
    est = comcore.estimate_posterior(square_mask, [(0, 20, 60, 20)], [(0.1, 3.0, 0.0)],
                                     model=None)
    with SessionLog(tmp_path / "a") as log:
        log.step(est, mask=square_mask, time=1.0)
        with pytest.raises(ValueError, match="time must increase"):
            log.step(est, time=0.5)
        with pytest.raises(ValueError, match=r"frame must have shape \(H, W\)"):
            log.step(est, frame=np.zeros((4, 4, 2)), time=2.0)
        with pytest.raises(TypeError, match="mask must be a comcore.Mask"):
            log.step(est, mask=np.ones((4, 4), bool), time=3.0)
    with pytest.raises(ValueError, match="exists"):
        SessionLog(tmp_path / "a")
    with pytest.raises(ValueError, match="closed"):
        log.step(est, time=9.0)
    with pytest.raises(ValueError, match="SessionLog's folder"):
        read_session_log(tmp_path)


def test_the_docs_figure_script_draws_a_logged_session(tmp_path):
    pytest.importorskip("matplotlib")
    require_simulators()
    from tests.scripts import run_script

    out = tmp_path / "log.png"
    printed = run_script("benchmarks/figures/session_log_figure.py", "--out", str(out))
    assert "steps logged" in printed and out.stat().st_size > 10_000

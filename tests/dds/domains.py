"""ROS domains for keel's DDS tests (ros2_peer_test.py, redundancy_test.py): each test takes a
ROS_DOMAIN_ID no other test of this machine holds, so that tests running in parallel never
hear each other."""
import fcntl
import random

_held = []  # lock files kept open: a domain is this process's until it exits


def domain():
    """A ROS_DOMAIN_ID (1-100), held by an flock on /tmp/keel-ros-domain-N until the process ends."""
    for d in random.sample(range(1, 101), 100):
        f = open(f"/tmp/keel-ros-domain-{d}", "a")
        try:
            fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            f.close()
            continue
        _held.append(f)
        return d
    raise RuntimeError("every ROS domain 1-100 is held by another test")

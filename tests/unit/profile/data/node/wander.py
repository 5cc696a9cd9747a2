#!/usr/bin/env python3
# A stand-in for a ROS 2 node's program: the profile tests only look it up, never run it.

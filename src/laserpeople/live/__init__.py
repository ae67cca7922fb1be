"""Live tracking on a running ROS 2 robot, over Zenoh, without ROS installed.

Modules: :mod:`.messages` (CDR in and out through rosbags' serialisers), :mod:`.keys` (key
expressions of ``zenoh-bridge-ros2dds`` and ``rmw_zenoh``), :mod:`.zenoh_link` (session,
subscriptions, publishers), :mod:`.poses` (transforms as they arrive), :mod:`.source`
(bounded per-laser queues, time jumps, frames), :mod:`.sinks` (publishing, latency),
:mod:`.runner` (the run), :mod:`.foxglove` (live viewer), :mod:`.replay` (a bag played
into Zenoh). Zenoh and the Foxglove SDK are imported only when used (the ``live`` extra).
"""

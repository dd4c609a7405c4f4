"""The ending the test helpers' rclpy nodes share (ros2_audio_dump, ros2_diagnostics_listener,
ros2_motion_recorder): say `ready` on stdout, then spin until SIGTERM shuts rclpy down."""
import signal


def spin_until_sigterm(rclpy, node, ready):
    signal.signal(signal.SIGTERM, lambda *_: rclpy.try_shutdown())
    print(ready, flush=True)
    try:
        rclpy.spin(node)
    except Exception:  # noqa: BLE001  (shut down by a signal)
        pass

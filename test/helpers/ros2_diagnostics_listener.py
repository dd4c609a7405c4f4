"""Test helper, a process of its own: every status name seen on /diagnostics (rclpy), one per
line in OUT, as they arrive.    python ros2_diagnostics_listener.py OUT"""
import signal
import sys


def main():
    import rclpy
    from diagnostic_msgs.msg import DiagnosticArray
    out = open(sys.argv[1], 'a')

    def got(m):
        for s in m.status:
            out.write('%s\t%d\t%s\n' % (s.name, s.level[0] if isinstance(s.level, bytes) else s.level, s.message))
        out.flush()
    rclpy.init()
    node = rclpy.create_node('diagnostics_listener')
    node.create_subscription(DiagnosticArray, '/diagnostics', got, 50)
    signal.signal(signal.SIGTERM, lambda *_: rclpy.try_shutdown())
    print('listener up', flush=True)
    try:
        rclpy.spin(node)
    except Exception:  # noqa: BLE001  (shut down by a signal)
        pass


if __name__ == '__main__':
    main()

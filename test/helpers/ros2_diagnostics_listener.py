"""Test helper, a process of its own: every status name seen on /diagnostics (rclpy), one per
line in OUT, as they arrive.    python ros2_diagnostics_listener.py OUT"""
import sys

from ros2_spin import spin_until_sigterm


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
    spin_until_sigterm(rclpy, node, 'listener up')


if __name__ == '__main__':
    main()

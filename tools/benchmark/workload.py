"""The benchmark's workload: the streams of issue 12 and the temporary topics, input and
expectations files that point sensorTest at them."""
import os
from typing import List, Tuple

# sensor, topic, kind, width, height, rate (for the microphone: samples a channel, channels,
# buffers a second)
Stream = Tuple[str, str, str, int, int, float]
STREAMS: List[Stream] = [
    ('frontCamera', '/bench/front/image_raw', 'rgb8', 640, 480, 30.0),
    ('bottomCamera', '/bench/bottom/image_raw', 'rgb8', 640, 480, 30.0),
    ('depthCamera', '/bench/depth/image_raw', '16UC1', 320, 240, 20.0),
    ('realsenseRGBCamera', '/bench/color/image_raw', 'rgb8', 640, 480, 30.0),
    ('realsenseDepthCamera', '/bench/aligned_depth_to_color/image_raw', '16UC1', 640, 480, 30.0),
    ('microphone', '/bench/audio', 'audio', 4096, 4, 48000.0 / 4096),
]
RING = 24   # distinct frames per stream, cycled (no two consecutive frames identical)


def topics() -> List[str]:
    """The benchmark's topics, in STREAMS' order."""
    return [s[1] for s in STREAMS]


def expectations() -> str:
    """The temporary expectations file: the streams' rates, encodings and sizes."""
    lines = ['# written by sensorTestBenchmark: the benchmark streams\' rates; the publisher stops',
             '# before the window ends, so a quiet tail of up to 5 s is accepted (max_gap_factor).',
             'defaults:', '  min_messages: 3', '  max_delay: 5.0', '  max_future: 1.0', 'robot:']
    for name, _, enc, w, h, rate in STREAMS:
        lines.append('  %s:' % name)
        lines.append('    rate: [%.2f, %.2f]' % (rate * 0.8, rate * 1.25))
        lines.append('    nominal: %.2f' % rate)
        lines.append('    max_gap_factor: %.1f' % (5.0 * rate * 0.8))
        if enc == 'audio':
            lines += ['    sample_rate: 48000', '    sample_rate_tolerance: 0.05', '    silence_dbfs: -70.0']
        else:
            lines.append('    encoding: %s' % enc)
            lines.append('    width: %d' % w)
            lines.append('    height: %d' % h)
            if enc == '16UC1':
                lines.append('    video_range: [0.0, 5.0]')
    return '\n'.join(lines) + '\n'


def write_files(folder: str) -> Tuple[str, str, str]:
    """Write the topics, input and expectations files into `folder`; their paths."""
    paths = (os.path.join(folder, 'benchTopics.dat'), os.path.join(folder, 'benchInput.ini'),
             os.path.join(folder, 'benchExpectations.yaml'))
    with open(paths[0], 'w') as f:
        f.writelines('%s %s\n' % (s[0], s[1]) for s in STREAMS)
    with open(paths[1], 'w') as f:
        f.writelines('%s true\n' % s[0] for s in STREAMS)
    with open(paths[2], 'w') as f:
        f.write(expectations())
    return paths

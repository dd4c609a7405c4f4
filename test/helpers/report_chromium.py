"""Test helper: open an HTML file in real headless Chromium and report what a viewer would see.

Chromium is driven through its DevTools protocol (remote debugging over a websocket, the
websocket-client package), because one browser session then gives everything at once:
  * console errors (Runtime.consoleAPICalled 'error'/'assert'), uncaught exceptions
    (Runtime.exceptionThrown), browser log errors (Log.entryAdded, e.g. "Failed to load
    resource") and failed requests (Network.loadingFailed, HTTP status >= 400);
  * the state of every <img> (loaded, natural size) and every <video>/<audio> (metadata loaded,
    duration, MediaError code) after the page has loaded;
  * the DOM as rendered (document.documentElement.outerHTML), so section ids can be checked,
    the page's visible text (document.body.innerText), every link's href and media src, and
    the number of <script> elements;
  * the page's scroll width against the window's width (`scroll_width`, `inner_width`) and the
    outermost elements that run past the right edge (`wide`); each verdict badge's text and
    height and right edge against its table cell's (`badges`);
  * a PNG screenshot of the whole page (the viewport is resized to the page's height).
`--dump-dom` and `--screenshot` would each need their own Chromium start and say nothing about
console errors or broken media.

usage from a test:  page = render_page('/path/report.html', '/tmp/out.png')
                    page.problems() -> [] when the page loaded cleanly
command line:       python test/helpers/report_chromium.py report.html out.png
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.request

import websocket

CHROMIUM_FLAGS = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
                  '--disable-background-networking', '--disable-component-update', '--disable-sync',
                  '--mute-audio', '--remote-debugging-port=0', '--remote-allow-origins=*']

PAGE_STATE_JS = r'''
(() => {
  const imgs = [...document.images].map(i => ({alt: i.alt, complete: i.complete, cls: i.className,
                                              width: i.naturalWidth, height: i.naturalHeight,
                                              shown: i.getBoundingClientRect().width}));
  const media = [...document.querySelectorAll('video, audio')].map(m => ({
      tag: m.tagName.toLowerCase(), ready: m.readyState, duration: m.duration,
      error: m.error ? m.error.code : null, width: m.videoWidth || 0,
      src: (m.currentSrc || '').slice(0, 40)}));
  const sections = [...document.querySelectorAll('section[id]')].map(s => s.id);
  const boxes = Object.fromEntries([...document.querySelectorAll('section[id]')].map(
      s => [s.id, [s.offsetTop, s.offsetTop + s.offsetHeight]]));
  const hrefs = [...document.querySelectorAll('a[href]')].map(a => a.getAttribute('href'));
  const mediaSrcs = [...document.querySelectorAll('video, audio')].map(m => m.getAttribute('src') || '');
  // what runs past the window's right edge (the page then scrolls sideways): the outermost
  // such elements not inside a box of their own that scrolls or clips, each as tag.class and
  // the start of its text
  const clipped = e => { for (let a = e.parentElement; a && a !== document.body; a = a.parentElement) {
      if (getComputedStyle(a).overflowX !== 'visible') return true; } return false; };
  const over = [...document.body.querySelectorAll('*')].filter(
      e => e.getBoundingClientRect().right > window.innerWidth + 0.5 && !clipped(e));
  const wide = over.filter(e => !over.includes(e.parentElement)).slice(0, 10).map(
      e => e.tagName.toLowerCase() + (e.className ? '.' + e.className : '') + ' ' +
           Math.round(e.getBoundingClientRect().right) + 'px: ' + (e.textContent || '').slice(0, 60));
  // each verdict badge: its text, height and right edge, and its table cell's right edge
  const badges = [...document.querySelectorAll('.badge')].map(b => ({text: b.textContent,
      height: b.getBoundingClientRect().height, right: b.getBoundingClientRect().right,
      cell_right: b.closest('td, th') ? b.closest('td, th').getBoundingClientRect().right : null}));
  return JSON.stringify({imgs, media, sections, boxes, title: document.title, hrefs, mediaSrcs, badges,
                         scroll_width: document.documentElement.scrollWidth, inner_width: window.innerWidth,
                         wide,
                         scripts: document.querySelectorAll('script').length,
                         text: document.body.innerText, alltext: document.body.textContent,
                         height: document.documentElement.scrollHeight});
})()
'''


def chromium_binary():
    for name in ('chromium', 'chromium-browser', 'google-chrome'):
        path = shutil.which(name)
        if path:
            return path
    return None


class Page:
    def __init__(self):
        self.console_errors = []
        self.exceptions = []
        self.log_errors = []
        self.failed_requests = []
        self.state = {}
        self.dom = ''
        self.screenshot = None
        self.load_seconds = None
        self.total_seconds = None

    def problems(self):
        """Everything that says the page did not load cleanly, as text lines."""
        out = ['console error: ' + x for x in self.console_errors]
        out += ['exception: ' + x for x in self.exceptions]
        out += ['log error: ' + x for x in self.log_errors]
        out += ['failed request: ' + x for x in self.failed_requests]
        for img in self.state.get('imgs', []):
            if not img['complete'] or not img['width']:
                out.append('image not loaded: %s' % img['alt'])
        for m in self.state.get('media', []):
            if m['error'] is not None or m['ready'] < 1:
                out.append('%s not playable: ready %s, error %s, src %s' % (m['tag'], m['ready'], m['error'], m['src']))
        return out


class _Cdp:
    def __init__(self, url, timeout=60):
        self.ws = websocket.create_connection(url, timeout=timeout, suppress_origin=True)
        self.next_id = 0
        self.events = []

    def call(self, method, timeout=60, **params):
        self.next_id += 1
        my_id = self.next_id
        self.ws.send(json.dumps({'id': my_id, 'method': method, 'params': params}))
        deadline = time.monotonic() + timeout
        while True:
            self.ws.settimeout(max(0.1, deadline - time.monotonic()))
            msg = json.loads(self.ws.recv())
            if msg.get('id') == my_id:
                if 'error' in msg:
                    raise RuntimeError('%s: %s' % (method, msg['error']))
                return msg.get('result', {})
            if 'method' in msg:
                self.events.append(msg)
            if time.monotonic() > deadline:
                raise TimeoutError(method)

    def wait_event(self, name, timeout):
        deadline = time.monotonic() + timeout
        for e in self.events:
            if e['method'] == name:
                return e
        while time.monotonic() < deadline:
            self.ws.settimeout(max(0.1, deadline - time.monotonic()))
            try:
                msg = json.loads(self.ws.recv())
            except websocket.WebSocketTimeoutException:
                break
            if 'method' in msg:
                self.events.append(msg)
                if msg['method'] == name:
                    return msg
        raise TimeoutError('no %s within %.0f s' % (name, timeout))

    def close(self):
        try:
            self.ws.close()
        except Exception:
            pass


def _debugger_url(user_dir, proc, timeout=30):
    port_file = os.path.join(user_dir, 'DevToolsActivePort')
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if proc.poll() is not None:
            raise RuntimeError('chromium exited with %s' % proc.returncode)
        if os.path.exists(port_file):
            lines = open(port_file).read().split()
            if lines:
                port = int(lines[0])
                with urllib.request.urlopen('http://127.0.0.1:%d/json/list' % port, timeout=5) as f:
                    targets = json.load(f)
                pages = [t for t in targets if t.get('type') == 'page']
                if pages:
                    return pages[0]['webSocketDebuggerUrl']
        time.sleep(0.1)
    raise TimeoutError('chromium did not open its debugging port')


def render_page(html_path, png_path=None, width=1400, media_wait=15.0, max_height=30000):
    """Load `html_path` in headless Chromium; returns a Page (see module docstring)."""
    binary = chromium_binary()
    if binary is None:
        raise RuntimeError('chromium is not installed (tools/setup.sh --test installs it)')
    user_dir = tempfile.mkdtemp(prefix='report-chromium-')
    page = Page()
    t_start = time.monotonic()
    log = open(os.path.join(user_dir, 'chromium.log'), 'w')
    proc = subprocess.Popen([binary] + CHROMIUM_FLAGS + ['--user-data-dir=' + user_dir,
                                                         '--window-size=%d,1000' % width, 'about:blank'],
                            stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    cdp = None
    try:
        cdp = _Cdp(_debugger_url(user_dir, proc))
        for domain in ('Page', 'Runtime', 'Log', 'Network'):
            cdp.call(domain + '.enable')
        cdp.call('Emulation.setDeviceMetricsOverride', width=width, height=1000, deviceScaleFactor=1, mobile=False)
        t_nav = time.monotonic()
        cdp.call('Page.navigate', url='file://' + os.path.abspath(html_path))
        cdp.wait_event('Page.loadEventFired', 90)
        page.load_seconds = time.monotonic() - t_nav
        deadline = time.monotonic() + media_wait
        while True:     # media elements load their metadata after the load event
            state = json.loads(cdp.call('Runtime.evaluate', expression=PAGE_STATE_JS,
                                        returnByValue=True)['result']['value'])
            pending = [m for m in state['media'] if m['ready'] < 1 and m['error'] is None]
            if not pending or time.monotonic() > deadline:
                break
            time.sleep(0.2)
        page.state = state
        page.dom = cdp.call('Runtime.evaluate', expression='document.documentElement.outerHTML',
                            returnByValue=True)['result']['value']
        if png_path:
            height = min(max_height, int(state['height']) + 20)
            cdp.call('Emulation.setDeviceMetricsOverride', width=width, height=height,
                     deviceScaleFactor=1, mobile=False)
            shot = cdp.call('Page.captureScreenshot', format='png', captureBeyondViewport=True, timeout=120)
            import base64
            with open(png_path, 'wb') as f:
                f.write(base64.b64decode(shot['data']))
            page.screenshot = png_path
        # drain events that arrived meanwhile
        try:
            cdp.wait_event('Test.never', 0.3)
        except TimeoutError:
            pass
        urls = {}
        for e in cdp.events:
            m, p = e['method'], e.get('params', {})
            if m == 'Runtime.consoleAPICalled' and p.get('type') in ('error', 'assert'):
                page.console_errors.append(' '.join(str(a.get('value', a.get('description', '')))
                                                    for a in p.get('args', [])))
            elif m == 'Runtime.exceptionThrown':
                d = p.get('exceptionDetails', {})
                page.exceptions.append(d.get('text', '') + ' ' + str(d.get('exception', {}).get('description', '')))
            elif m == 'Log.entryAdded' and p.get('entry', {}).get('level') == 'error':
                entry = p['entry']
                page.log_errors.append('%s %s' % (entry.get('text'), entry.get('url', '')))
            elif m == 'Network.requestWillBeSent':
                urls[p.get('requestId')] = p.get('request', {}).get('url', '')[:80]
            elif m == 'Network.loadingFailed':
                # a <video>/<audio> stops its own request once it has what preload asks for
                # (net::ERR_ABORTED, type Media); whether media loaded is checked on the element
                if p.get('type') == 'Media' and p.get('errorText') == 'net::ERR_ABORTED':
                    continue
                page.failed_requests.append('%s %s %s' % (p.get('errorText'), p.get('type'),
                                                          urls.get(p.get('requestId'), '?')))
            elif m == 'Network.responseReceived':
                status = p.get('response', {}).get('status', 0)
                if status >= 400:
                    page.failed_requests.append('%s %s' % (status, p['response'].get('url', '')[:80]))
    finally:
        if cdp is not None:
            cdp.close()
        if proc.poll() is None:
            proc.terminate()
            try:
                proc.wait(10)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()
        log.close()
        shutil.rmtree(user_dir, ignore_errors=True)
    page.total_seconds = time.monotonic() - t_start
    return page


if __name__ == '__main__':
    p = render_page(sys.argv[1], sys.argv[2] if len(sys.argv) > 2 else None)
    print(json.dumps({'problems': p.problems(), 'sections': p.state.get('sections'),
                      'media': p.state.get('media'), 'load_s': round(p.load_seconds, 2),
                      'total_s': round(p.total_seconds, 2)}, indent=1))

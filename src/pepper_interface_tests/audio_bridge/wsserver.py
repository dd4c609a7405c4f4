"""The audio bridge's websocket server, one plain thread per connection, on either websockets API.

websockets 11.0 and later: its own threaded server (``websockets.sync.server``, 11.0's
changelog). Before 11.0 (Ubuntu 20.04's python3-websockets is 8.1) there is only the asyncio
server: it is run here on an event loop of its own in the thread that calls ``serve_forever``,
and each connection's handler in a thread of its own, behind a connection object with the
sync API's four members the bridge uses (``remote_address``, iteration over the messages,
``close(code, reason)``, ``respond(status, text)`` at the handshake). Either way the handler is
called with one connection and returns when the peer goes away; ``process_request(connection,
request)`` sees ``request.headers`` and returns None or ``connection.respond(...)``.
"""
import asyncio
import logging
import threading
from typing import Any, Callable, List, Optional, Tuple

SHUTDOWN_S = 5.0   # the asyncio server's closing handshakes; the sync server's shutdown waits too


def serve(handler: Callable[[Any], None], host: str, port: int, max_size: int,
          process_request: Callable[[Any, Any], Any], logger: logging.Logger) -> Any:
    """A bound server (raises OSError when the port cannot be bound) with ``serve_forever()``,
    ``shutdown()`` and ``socket``."""
    try:
        from websockets.sync.server import serve as sync_serve
    except ImportError:   # websockets < 11.0
        return AsyncioServer(handler, host, port, max_size, process_request, logger)
    return sync_serve(handler, host, port, compression=None, max_size=max_size,
                      process_request=process_request, logger=logger)


def closed_oversized(exc: Exception) -> bool:
    """Whether a ConnectionClosed ended a connection whose peer sent a message over max_size.
    websockets 10.0 and later say it in ``exc.sent`` (the close frame sent: code 1009); 8.1's
    exception carries the close code received (1006 here: the connection was failed) and the
    cause, PayloadTooBig, as ``__cause__`` (8.1 protocol.py connection_closed_exc)."""
    if hasattr(exc, 'sent'):
        sent = exc.sent
        return sent is not None and sent.code == 1009
    from websockets.exceptions import PayloadTooBig
    return isinstance(exc.__cause__, PayloadTooBig)


class _Request:
    def __init__(self, path: str, headers: Any) -> None:
        self.path, self.headers = path, headers


class _Connection:
    """One asyncio connection seen from its handler's thread."""

    def __init__(self, proto: Any, loop: asyncio.AbstractEventLoop) -> None:
        self._proto, self._loop = proto, loop

    @property
    def remote_address(self) -> Any:
        return self._proto.remote_address

    def __iter__(self) -> Any:
        """The messages until the peer closes (1000/1001: the end; any other close raises
        ConnectionClosed, as the sync API does)."""
        from websockets.exceptions import ConnectionClosedOK
        while True:
            try:
                yield self._call(self._proto.recv())
            except ConnectionClosedOK:
                return

    def close(self, code: int = 1000, reason: str = '') -> None:
        self._call(self._proto.close(code, reason))

    def respond(self, status: Any, text: str) -> Tuple[Any, List[Tuple[str, str]], bytes]:
        """The handshake's HTTP response, as 8.1's process_request returns it."""
        return status, [('Content-Type', 'text/plain; charset=utf-8')], text.encode('utf-8')

    def _call(self, coroutine: Any) -> Any:
        return asyncio.run_coroutine_threadsafe(coroutine, self._loop).result()


class AsyncioServer:
    """websockets < 11.0: the asyncio server on a loop of its own, handlers in threads."""

    def __init__(self, handler: Callable[[Any], None], host: str, port: int, max_size: int,
                 process_request: Callable[[Any, Any], Any], logger: logging.Logger) -> None:
        # websockets < 11.0 only; today's stubs know these names under websockets.legacy
        from websockets.server import WebSocketServerProtocol  # type: ignore[attr-defined]
        from websockets.server import serve as asyncio_serve  # type: ignore[attr-defined]
        # 8.1 logs through the module loggers under 'websockets', not a logger= argument
        logging.getLogger('websockets').setLevel(logger.getEffectiveLevel())
        self.loop = loop = asyncio.new_event_loop()

        class Protocol(WebSocketServerProtocol):  # type: ignore[misc,valid-type]
            async def process_request(self, path: str, headers: Any) -> Any:
                return process_request(_Connection(self, loop), _Request(path, headers))

        async def run_handler(proto: Any, path: str) -> None:
            done = loop.create_future()

            def run() -> None:
                try:
                    handler(_Connection(proto, loop))
                finally:
                    if not loop.is_closed():
                        loop.call_soon_threadsafe(_finish, done)
            threading.Thread(target=run, name='websocket-connection', daemon=True).start()
            await done

        self.server = loop.run_until_complete(asyncio_serve(
            run_handler, host, port, compression=None, max_size=max_size,
            create_protocol=Protocol, loop=loop))
        self.socket = self.server.sockets[0]

    def serve_forever(self) -> None:
        self.loop.run_forever()

    def shutdown(self) -> None:
        """Close every connection (1001) and stop the loop; at most SHUTDOWN_S s."""
        async def close() -> None:
            self.server.close()
            await self.server.wait_closed()
        if self.loop.is_running():
            try:
                asyncio.run_coroutine_threadsafe(close(), self.loop).result(SHUTDOWN_S)
            except Exception:  # noqa: BLE001  (a peer that does not close in time)
                pass
            self.loop.call_soon_threadsafe(self.loop.stop)
        else:
            self.server.close()


def _finish(done: 'Optional[asyncio.Future[None]]') -> None:
    if done is not None and not done.done():
        done.set_result(None)

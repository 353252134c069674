"""The material viewer's local server (slicecap-viewer ... --serve [PORT], docs/material-viewer.md):
the pages already built, served from memory on the loopback interface only, so a browser on the
same machine opens them by URL; the pages are self-contained, nothing else is served or fetched.
"""

import http.server
import ipaddress
import os
import signal
import threading
from collections.abc import Sequence
from types import FrameType

LOOPBACK = "127.0.0.1"


def _handler(pages: dict[str, bytes]) -> type[http.server.BaseHTTPRequestHandler]:
    class PageHandler(http.server.BaseHTTPRequestHandler):
        def _send(self, with_body: bool) -> None:
            body = pages.get(self.path.split("?", 1)[0].split("#", 1)[0])
            if body is None:
                self.send_error(404, "not one of the viewer's pages")
                return
            self.send_response(200)
            self.send_header("Content-Type", "text/html; charset=utf-8")
            self.send_header("Content-Length", str(len(body)))
            self.send_header("Cache-Control", "no-store")
            self.end_headers()
            if with_body:
                self.wfile.write(body)

        def do_GET(self) -> None:  # the name http.server calls
            self._send(True)

        def do_HEAD(self) -> None:
            self._send(False)

        def log_message(self, format: str, *args: object) -> None:
            pass  # one line a request would bury the URL printed for the user

    return PageHandler


def make_server(
    pages: dict[str, bytes], port: int = 0, host: str = LOOPBACK
) -> http.server.ThreadingHTTPServer:
    """A server (not yet serving) of `pages` (URL path, e.g. "/", to the page's bytes) bound to
    host:port, port 0 picking a free one (server.server_address says which). Raises ValueError
    when host is not a loopback address (the viewer serves only this machine), OSError when the
    port cannot be bound (in use, or below 1024 without the right)."""
    try:
        loopback = ipaddress.ip_address(host).is_loopback
    except ValueError:
        loopback = False
    if not loopback:
        raise ValueError(f"{host}: not a loopback address; the viewer serves 127.0.0.1 only")
    server = http.server.ThreadingHTTPServer((host, port), _handler(pages))
    server.daemon_threads = True
    # Closing the server does not wait for requests still being answered: a browser that keeps a
    # connection open would otherwise hold Ctrl-C's exit for as long as it likes.
    server.block_on_close = False
    return server


def _interrupt(signum: int, frame: FrameType | None) -> None:
    raise KeyboardInterrupt


def _how_to_stop() -> str:
    # A job a non-interactive shell starts in the background inherits SIGINT ignored, and Python
    # then raises no KeyboardInterrupt: Ctrl-C cannot stop such a server, SIGTERM still does.
    if signal.getsignal(signal.SIGINT) == signal.SIG_IGN:
        return (f"Ctrl-C is ignored (started with SIGINT ignored, as a background job is): "
                f"kill {os.getpid()} stops the server")
    return "Ctrl-C stops the server"


def serve_until_interrupted(server: http.server.ThreadingHTTPServer, urls: Sequence[str]) -> None:
    """Serves on a thread of its own until Ctrl-C (SIGINT) or SIGTERM, printing "serving URL" for
    each of `urls`, then how to stop it ("Ctrl-C stops the server", or that Ctrl-C is ignored and
    `kill PID` stops it). Returns once the serving loop has ended.

    The main thread only waits here, so the interrupt lands in that wait and nowhere inside the
    server's own loop; SIGTERM is taken for the same stop from the line before the first URL is
    printed on, so a signal sent once a URL is known always stops the server, and both handlers
    are given back on return."""
    serving = threading.Thread(target=server.serve_forever, name="viewer-server", daemon=True)
    previous = signal.signal(signal.SIGTERM, _interrupt)
    try:
        serving.start()
        for url in urls:
            print(f"serving {url}", flush=True)
        print(_how_to_stop(), flush=True)
        while serving.is_alive():
            serving.join(timeout=1.0)  # a signal delivered to another thread is seen within 1 s
    except KeyboardInterrupt:
        pass
    finally:
        # shutdown() waits for a loop that started; one that never ran would be waited for forever.
        if serving.ident is not None:
            server.shutdown()
        signal.signal(signal.SIGTERM, previous)


def page_url(server: http.server.ThreadingHTTPServer, path: str) -> str:
    """The URL of the page at `path` on `server`."""
    host, port = server.server_address[:2]
    return f"http://{host!s}:{port}{path}"

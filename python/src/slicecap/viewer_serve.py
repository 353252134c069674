"""The material viewer's local server (slicecap-viewer ... --serve [PORT], docs/material-viewer.md):
the pages already built, served from memory on the loopback interface only, so a browser on the
same machine opens them by URL; the pages are self-contained, nothing else is served or fetched.
"""

import http.server
import ipaddress

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
    return server


def page_url(server: http.server.ThreadingHTTPServer, path: str) -> str:
    """The URL of the page at `path` on `server`."""
    host, port = server.server_address[:2]
    return f"http://{host!s}:{port}{path}"

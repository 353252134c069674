"""The viewer's HTML page: viewer_page.html with its placeholders, data and script filled in.

Shared by the table viewer (viewer.py) and the SVBRDF maps page (viewer_maps_page.py).
"""

import importlib.resources
import json


def fill_template(replacements: dict[str, str], data: dict) -> str:
    """viewer_page.html with its placeholders, the page data and the script filled in."""
    package = importlib.resources.files("slicecap")
    template = (package / "viewer_page.html").read_text(encoding="utf-8")
    replacements = {
        **replacements,
        # "</" inside a script element would end it early.
        "{{DATA}}": json.dumps(data).replace("</", "<\\/"),
        "{{SCRIPT}}": (package / "viewer_page.js").read_text(encoding="utf-8"),
    }
    for key, value in replacements.items():
        template = template.replace(key, value)
    return template

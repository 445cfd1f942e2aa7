"""mkdocs hooks: the build's one known docstring warning, filtered by its exact source.

``comcore.paper.estimate_heatmap``'s docstring holds a paragraph inside its Parameters
section, which griffe's numpy parser reads as parameters (``No types or annotations for
parameters ['Alg']`` ...). The filter drops griffe's warnings about that docstring only
(``comcore/paper/_heatmap.py:125``); every other docstring warning still fails
``mkdocs build --strict``. Delete this file (and ``hooks:`` in mkdocs.yml) once the paragraph
moves above the Parameters section.
"""

from __future__ import annotations

import logging

KNOWN = ("comcore/paper/_heatmap.py:125:",)


class _KnownDocstringWarnings(logging.Filter):
    def filter(self, record: logging.LogRecord) -> bool:
        message = str(record.getMessage()).removeprefix("griffe: ")
        return not message.startswith(KNOWN)


def on_startup(command, dirty):
    logging.getLogger("mkdocs.plugins.griffe").addFilter(_KnownDocstringWarnings())

"""Where the chit-chat training pairs' text lies, read in place and never copied: the Papaya
``Q:``/``A:`` files of the configured folder and the English YAML files of the installed
``chatterbot-corpus`` package.

The training readers and the retrieval pool both read through these functions, so a pool
reference names exactly the line that training read. A reference is
``(source, file, first, second)``:

* ``("papaya", "misc_new.txt", q, a)``: the ``Q:`` line ``q`` and the ``A:`` line ``a``
  (0-based line numbers) of that file in the Papaya folder;
* ``("chatterbot", "greetings.yml", c, i)``: lines ``i`` and ``i + 1`` of conversation
  ``c`` of that file of the package.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from importlib import resources
from pathlib import Path
from typing import Any

import yaml

from core.errors import UserError
from core.files import read_text

FILE_LIMIT = 64 << 20   # bytes: a Papaya file (the largest shipped one has 87 kB)
FUNC = re.compile(r"_func_val_\S*")  # a client function (show a picture, tell the time)
_LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)  # the C parser: ten times faster

Ref = tuple[str, str, int, int]


def papaya_lines(path: Path) -> list[str]:
    """The lines of a Papaya file, as training numbers them."""
    return read_text(path, FILE_LIMIT).splitlines()


def papaya_pair(q_line: str, a_line: str) -> tuple[str, str]:
    """The (input, reply) text of a ``Q:`` and an ``A:`` line, client functions removed."""
    return q_line.strip()[2:], FUNC.sub(" ", a_line.strip()[2:])


def chatterbot_dir() -> Path | None:
    """The English folder of the installed ``chatterbot-corpus`` package (None without it)."""
    try:
        return Path(str(resources.files("chatterbot_corpus") / "data" / "english"))
    except ModuleNotFoundError:
        return None


def chatterbot_conversations(path: Path) -> list[list[str]]:
    """The lines of each conversation of a chatterbot YAML file (empty entries left out;
    a conversation's position in the file is its index here)."""
    doc = yaml.load(read_text(path, FILE_LIMIT), Loader=_LOADER)
    convs = doc.get("conversations") if isinstance(doc, dict) else None
    return [[str(x) for x in lines or [] if x is not None] for lines in convs or []]


class SourceTexts:
    """The raw (input, reply) text behind references, each file read once.

    ``papaya_dir`` is the Papaya folder (None: no Papaya). A reference whose file, folder,
    package or line is missing gives None; so does one naming a path instead of a file.
    """

    def __init__(self, papaya_dir: Path | None) -> None:
        self.papaya_dir = papaya_dir
        self._papaya: dict[str, list[str] | None] = {}
        self._chatterbot: dict[str, list[list[str]] | None] = {}

    def text(self, ref: Ref) -> tuple[str, str] | None:
        """The (input, reply) text that ``ref`` points to, or None where it cannot be read."""
        source, name, first, second = ref
        if Path(name).name != name or min(first, second) < 0:
            return None
        if source == "papaya":
            lines = self._read(self._papaya, name, self._papaya_file)
            if lines is None or max(first, second) >= len(lines):
                return None
            return papaya_pair(lines[first], lines[second])
        if source == "chatterbot":
            convs = self._read(self._chatterbot, name, self._chatterbot_file)
            if convs is None or first >= len(convs) or second + 1 >= len(convs[first]):
                return None
            return convs[first][second], convs[first][second + 1]
        return None

    @staticmethod
    def _read(cache: dict, name: str, reader: Callable[[str], Any]) -> Any:
        if name not in cache:
            try:
                cache[name] = reader(name)
            except (UserError, yaml.YAMLError):
                cache[name] = None
        return cache[name]

    def _papaya_file(self, name: str) -> list[str] | None:
        return None if self.papaya_dir is None else papaya_lines(self.papaya_dir / name)

    @staticmethod
    def _chatterbot_file(name: str) -> list[list[str]] | None:
        folder = chatterbot_dir()
        return None if folder is None else chatterbot_conversations(folder / name)

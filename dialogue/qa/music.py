"""Play-music category: start the sing/dance skill with one of the songs the robot knows."""

from __future__ import annotations

import re
from urllib.parse import quote_plus

from dialogue.qa.base import Action, Answer
from dialogue.qa.text import normalise, word_set

SONGS = ("happy birthday", "twinkle twinkle little star", "you are my sunshine")
DEFAULT_SONG = "you are my sunshine"
CUES = {"happy birthday": ("happy birthday", "birthday"),
        "twinkle twinkle little star": ("twinkle", "little star"),
        "you are my sunshine": ("sunshine",)}
GENERIC = word_set("""a an the some any music song songs something anything tune tunes calm
nice happy cheerful relaxing soft quiet lively little favourite favorite us me dance dancing bit
few again please for with now to tonight one another more your our my you robot something's
melody lullaby play sing""")
QUOTED = re.compile(r"(?:^|(?<=\s))[\"'\u2018\u201c]([^\"\u2019\u201d]{2,60}?)"
                    r"[\"'\u2019\u201d](?=[\s?.!,;:]|$)")
ASK = re.compile(r"\b(?:play|sing|put on|hum)\s+(.+)$")


def _known(t: str) -> str | None:
    for song, cues in CUES.items():
        if any(f" {c} " in f" {t} " for c in cues):
            return song
    return None


def _asked_title(text: str) -> str | None:
    quoted = QUOTED.search(text)
    if quoted:
        return quoted.group(1).strip()
    m = ASK.search(normalise(text))
    if not m:
        return None
    words = re.split(r"\b(?:for|with|to|please|because|so)\b", m.group(1))[0].split()
    return " ".join(words) if any(w not in GENERIC for w in words) else None


def answer_music(text: str) -> Answer:
    """Ask the robot to sing and dance the named song (or its default one)."""
    t = normalise(text)
    song = _known(t)
    if song is None:
        title = _asked_title(text)
        if title and _known(normalise(title)) is None:
            known = ", ".join(s.title() for s in SONGS[:-1]) + f" or {SONGS[-1].title()}"
            title = title.title() if title.islower() else title
            return Answer(f"Sorry, I don't know {title} yet. I can sing {known}.",
                          found=False, topic=title)
        song = DEFAULT_SONG
    return Answer(f"Here comes {song.title()}! Let's sing and dance.",
                  tablet=f"https://www.youtube.com/results?search_query={quote_plus(song)}",
                  action=Action("sing_dance", {"song": song}), topic=song)

"""Play-music category: start the sing/dance skill with one of the songs the robot knows.

The songs the robot knows are its dance routines (``config/dances.yaml``, or the
routines file a run uses): asked for one of them, by its title or another name, it says so
and the skill dances that routine; asked for a song it does not know, it says which ones
it can sing; asked for "a song", it sings the first one.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from functools import cache
from urllib.parse import quote_plus

from dialogue.qa.base import Action, Answer
from dialogue.qa.text import normalise, word_set
from robot.dances import song_names

Songs = Mapping[str, Sequence[str]]   # title -> the phrases that ask for it


@cache
def shipped_songs() -> Songs:
    """The songs of the shipped routines file (``config/dances.yaml``)."""
    return song_names()

GENERIC = word_set("""a an the some any music song songs something anything tune tunes calm
nice happy cheerful relaxing soft quiet lively little favourite favorite us me dance dancing bit
few again please for with now to tonight one another more your our my you robot something's
melody lullaby play sing""")
QUOTED = re.compile(r"(?:^|(?<=\s))[\"'\u2018\u201c]([^\"\u2019\u201d]{2,60}?)"
                    r"[\"'\u2019\u201d](?=[\s?.!,;:]|$)")
ASK = re.compile(r"\b(?:play|sing|put on|hum)\s+(.+)$")
KINDS = word_set("music song songs tune tunes something anything melody")   # not titles
NAMING = word_set("called named titled")
MAX_TITLE_WORDS = 6   # longer unquoted "titles" are the rest of the sentence, or misheard


def _known(t: str, songs: Songs) -> str | None:
    for title, cues in songs.items():
        if any(f" {normalise(c)} " in f" {t} " for c in cues):
            return title
    return None


def _asked_title(text: str) -> str | None:
    quoted = QUOTED.search(text)
    if quoted:
        return quoted.group(1).strip()
    m = ASK.search(normalise(text))
    if not m:
        return None
    words = re.split(r"\b(?:for|with|to|please|because|so)\b", m.group(1))[0].split()
    lead = next((i for i, w in enumerate(words) if w not in GENERIC), len(words))
    title = words[lead:]
    if title and title[0] in NAMING:         # "a song called Yesterday"
        title = title[1:]
    elif any(w in KINDS for w in words[:lead]):   # "play music what is ...": no title said
        return None
    return " ".join(title) if 0 < len(title) <= MAX_TITLE_WORDS else None


def answer_music(text: str, songs: Songs | None = None) -> Answer:
    """Ask the robot to sing and dance the named song of ``songs`` (default: the shipped
    routines), or the first one."""
    songs = songs or shipped_songs()
    t = normalise(text)
    song = _known(t, songs)
    if song is None:
        title = _asked_title(text)
        if title and _known(normalise(title), songs) is None:
            names = list(songs)
            known = ", ".join(names[:-1]) + f" or {names[-1]}" if len(names) > 1 else names[0]
            title = title.title() if title.islower() else title
            return Answer(f"Sorry, I don't know {title} yet. I can sing {known}.",
                          found=False, topic=title)
        song = next(iter(songs))
    return Answer(f"Here comes {song}! Let's sing and dance.",
                  tablet=f"https://www.youtube.com/results?search_query={quote_plus(song)}",
                  action=Action("sing_dance", {"song": song}), topic=song)

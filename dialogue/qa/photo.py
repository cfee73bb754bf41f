"""Take-a-photo category: ask the robot for a photo; the caller saves the camera frame."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from dialogue.qa.base import Action, Answer

TakePhoto = Callable[[], str | Path]


def answer_photo(take: TakePhoto | None = None, name: str | None = None) -> Answer:
    """Return the ``take_photo`` action; with ``take`` (which saves a frame and returns its
    path) the photo is taken now and the tablet shows the file."""
    cheese = f"Say cheese, {name}!" if name else "Say cheese!"
    if take is None:
        return Answer(f"{cheese} I'm taking a photo now.", action=Action("take_photo"),
                      topic="photo")
    try:
        path = str(take())
    except Exception:  # a camera failure must not break the conversation
        return Answer("Sorry, my camera isn't working right now.", found=False, topic="photo")
    return Answer(f"{cheese} I took the photo; you can see it on my tablet.", tablet=path,
                  action=Action("take_photo", {"path": path}), topic="photo")

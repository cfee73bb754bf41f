"""``companion memory show FILE`` and ``companion memory reset FILE``."""

from __future__ import annotations

import argparse
from pathlib import Path


def add_commands(sub: argparse._SubParsersAction) -> None:
    """Register ``memory``."""
    p = sub.add_parser("memory", help="show or reset what a household taught the robot",
                       description="A household's memory file (docs/feedback.md): each "
                       "person's learnt preference for each action, and what each told about "
                       "themselves.")
    what = p.add_subparsers(dest="memory_command", required=True, metavar="WHAT")
    show = what.add_parser("show", help="print what each person told the robot and their "
                           "preferences")
    show.add_argument("file", type=Path)
    show.set_defaults(func=run_show)
    reset = what.add_parser("reset", help="forget every preference and everything told (the file "
                            "stays, empty)")
    reset.add_argument("file", type=Path)
    reset.set_defaults(func=run_reset)


def run_show(args: argparse.Namespace) -> int:
    """Handler of ``companion memory show``."""
    from mind.personality import ACTIONS
    from mind.preferences.memory import MemoryFileError, load_memory

    if not args.file.exists():
        raise MemoryFileError(f"{args.file}: no such memory file")
    memory = load_memory(args.file, "")
    print(f"household: {memory.household}")
    for who, facts in sorted(memory.facts.items()):
        for fact in facts:
            when = f" {fact.when}" if fact.when else ""
            asked = " (asked)" if fact.asked else ""
            print(f"{who} told: {fact.kind}: {fact.said}{when}{asked}")
    if not memory.prefs:
        print("no feedback yet")
        return 0
    print("| person | feedback | " + " | ".join(ACTIONS) + " |")
    print("|---|---|" + "---|" * len(ACTIONS))
    for who, row in sorted(memory.prefs.items()):
        print(f"| {who} | {memory.events.get(who, 0)} | "
              + " | ".join(f"{v:+.2f}" for v in row) + " |")
    return 0


def run_reset(args: argparse.Namespace) -> int:
    """Handler of ``companion memory reset``: an empty memory for the same household. A
    file that is not a memory file is left untouched (exit 2): a mistyped path must not
    destroy a scenario."""
    from mind.preferences.memory import Memory, load_memory, save_memory

    household = load_memory(args.file, args.file.stem).household
    save_memory(Memory(household), args.file)
    print(f"{args.file}: every preference forgotten")
    return 0

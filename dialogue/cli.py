"""Command line of the dialogue domain: ``companion chat`` and ``companion eval dialogue``.

Handlers import their heavy modules when called, so that ``companion --help`` stays fast.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
import time
from collections.abc import Iterable
from pathlib import Path
from typing import Any, TextIO

from core.cli_args import integer
from core.paths import WORLDS_DIR
from core.signals import Terminated
from dialogue.intent import HELDOUT_FILE, MODES
from dialogue.qa.base import DialogueError

DEFAULT_SCENARIO = WORLDS_DIR / "living_room.yaml"
ROUTING_BAR = 0.95
NOT_UTF8 = "standard input: not UTF-8 text"
HELP = """Type a question or just talk. Commands:
  /mode auto|qa|chitchat|<category>   route every line this way (the tablet buttons)
  /mood positive|negative|auto        force the mood, or go back to the computed one
  /context                            show what I remember
  /help, /quit"""


def add_commands(sub: argparse._SubParsersAction) -> None:
    """Register ``chat`` under the top-level subcommands."""
    p = sub.add_parser("chat", help="talk to the robot: QA bot and chit-chat, by mood",
                       description="Interactive dialogue with the robot. Each line is routed "
                                   "to a QA category or to chit-chat; the reply, any action "
                                   "and what the tablet shows are printed.")
    p.add_argument("--mood", choices=("positive", "negative"),
                   help="force the mood (default: computed from the robot's drives)")
    p.add_argument("--json", action="store_true",
                   help="scripting: read lines from stdin, print one JSON object per line")
    p.add_argument("--mode", choices=MODES, default="auto", help="route every line this way")
    p.add_argument("--scenario", type=Path, default=None,
                   help="scenario YAML for the household map and the robot's drives "
                        "(default: worlds/living_room.yaml for the map, drives all 0)")
    p.add_argument("--weather", type=Path, default=None,
                   help="weather block file (default: dialogue/data/weather_sample.yaml)")
    p.add_argument("--feed", type=Path, default=None,
                   help="RSS/Atom file for news (default: dialogue/data/news_sample.xml)")
    heard = p.add_mutually_exclusive_group()
    heard.add_argument("--audio", type=Path, default=None, metavar="FILE.wav",
                       help="transcribe this WAV file (16-bit PCM; several channels are taken "
                            "as the head's microphones) with the robot's speech recogniser, "
                            "answer it, and leave")
    heard.add_argument("--listen", action="store_true",
                       help="listen to the computer's default microphone: each time you stop "
                            "talking, what you said is transcribed and answered (Ctrl-C "
                            "leaves)")
    p.add_argument("--out", type=Path, default=None,
                   help="keep the session's maps, photos and reply log (dialogue.jsonl) in this "
                        "folder (default: a temporary folder, removed when the session ends, "
                        "however it ends)")
    p.set_defaults(func=run_chat)


def add_eval(sub: argparse._SubParsersAction) -> None:
    """Register ``dialogue`` under ``companion eval``."""
    p = sub.add_parser("dialogue", help="routing accuracy and reply latency on the held-out "
                                        "utterances")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--heldout", type=Path, default=HELDOUT_FILE,
                   help="labelled utterances (label<TAB>text)")
    p.set_defaults(func=run_eval)
    k = sub.add_parser("knowledge", help="the held-out knowledge questions (what is, who was, "
                                         "who invented), each answer marked by its keywords")
    k.add_argument("--json", action="store_true", help="print one JSON object")
    k.add_argument("--questions", type=Path, default=None,
                   help="questions file (kind<TAB>question<TAB>keyword|keyword; default: "
                        "dialogue/data/knowledge_questions.tsv)")
    k.set_defaults(func=run_eval_knowledge)
    c = sub.add_parser("conversation", help="acts, fitting replies, care signals, latency",
                       description="Answer the held-out conversation lines "
                       "(dialogue/data/conversation_test.tsv) and score act accuracy, "
                       "fitting replies (the rubric of docs/conversation.md), mood openings "
                       "that contradict the line, non sequiturs (MiniLM relevance), care "
                       "recall and false alerts, and reply latency on one thread.")
    c.add_argument("--lines", type=Path, help="held-out lines (default: the shipped set)")
    c.add_argument("--config", type=Path, help="YAML overriding config/acts.yaml")
    c.add_argument("--examples", type=integer(0, 1000), default=12,
                   help="examples to print, the robot's replies before and after")
    c.add_argument("--json", action="store_true", help="print one JSON object")
    c.set_defaults(func=run_eval_conversation)


def _print_reply(reply: Any, out: TextIO) -> None:
    print(f"robot [{reply.route}]: {reply.text}", file=out)
    if reply.action is not None:
        params = " ".join(f"{k}={v}" for k, v in reply.action.params.items())
        print(f"  action: {reply.action.name} {params}".rstrip(), file=out)
    if reply.tablet:
        print(f"  tablet: {reply.tablet}", file=out)


def _command(line: str, manager: Any, state: dict[str, Any], out: TextIO) -> bool:
    """Handle a /command; False means quit."""
    cmd, _, arg = line[1:].strip().partition(" ")
    arg = arg.strip()
    if cmd in ("quit", "exit", "q"):
        return False
    if cmd == "mode" and arg in MODES:
        manager.context.mode = arg
        print(f"mode: {arg}", file=out)
    elif cmd == "mood" and arg in ("positive", "negative", "auto"):
        state["mood"] = state["computed"] if arg == "auto" else arg
        print(f"mood: {state['mood']}", file=out)
    elif cmd == "context":
        c = manager.context
        print(f"name: {c.name}, last topic: {c.last_topic}, last route: {c.last_route}, "
              f"mode: {c.mode}", file=out)
    else:
        print(HELP, file=out)
    return True


def run_chat(args: argparse.Namespace, stdin: TextIO | None = None,
             stdout: TextIO | None = None) -> int:
    """The ``chat`` REPL (or, with ``--json``, one JSON reply per stdin line). Without
    ``--out`` the session's files go to a temporary folder that is removed on every way out:
    the end of the input, ``/quit``, an error, Ctrl-C or SIGTERM."""
    if args.out is not None:
        return _chat(args, args.out, stdin or sys.stdin, stdout or sys.stdout)
    with tempfile.TemporaryDirectory(prefix="companion-chat-") as tmp:
        return _chat(args, Path(tmp), stdin or sys.stdin, stdout or sys.stdout)


def _chat(args: argparse.Namespace, folder: Path, stdin: TextIO, out: TextIO) -> int:
    if args.listen:   # the microphone first: without one no model needs loading
        from dialogue.speech.listen import microphone

        with microphone() as blocks:
            return _listen(args, folder, blocks, out)
    from dialogue.factory import chat_session, robot_mood

    manager, drives, personality = chat_session(args.scenario, DEFAULT_SCENARIO, args.weather,
                                                args.feed, folder)
    manager.context.mode = args.mode
    computed, value, threshold = robot_mood(drives, personality)
    state = {"computed": computed, "mood": args.mood or computed}
    if args.audio is not None:
        return _answer_audio(args, manager, state["mood"], out)
    if args.json:
        try:
            for raw in stdin:
                reply = manager.respond(raw, state["mood"])
                print(json.dumps({"input": raw.rstrip("\n"), **reply.to_dict()}), file=out,
                      flush=True)
        except UnicodeDecodeError:
            raise DialogueError(NOT_UTF8) from None
        return 0
    source = "forced by --mood" if args.mood else (
        f"v_mood {value:.2f} {'<=' if computed == 'positive' else '>'} threshold "
        f"{threshold:g}, drives {'from the scenario' if drives else 'all 0'}")
    kept = "" if args.out else " (a temporary folder, removed when you leave; --out DIR keeps it)"
    print(f"Robot mood: {state['mood']} ({source}). Maps go to {folder}{kept}.", file=out)
    print("Type /help for commands, /quit to leave.", file=out, flush=True)
    interactive = stdin is sys.stdin
    while True:
        try:
            line = input("you> ") if interactive else _readline(stdin, out)
        except Terminated:
            raise
        except (EOFError, KeyboardInterrupt):  # Ctrl-D or Ctrl-C at the prompt: goodbye
            print(file=out)
            return 0
        except UnicodeDecodeError:
            raise DialogueError(NOT_UTF8) from None
        if line.strip().startswith("/"):
            if not _command(line, manager, state, out):
                return 0
            continue
        _print_reply(manager.respond(line, state["mood"]), out)
        out.flush()


def _answer_audio(args: argparse.Namespace, manager: Any, mood: str, out: TextIO) -> int:
    """``chat --audio FILE.wav``: what the recogniser heard in the file, and the answer."""
    from dialogue.speech.recognizer import SpeechRecognizer
    from dialogue.speech.wav import read_wav

    samples, rate = read_wav(args.audio, all_channels=True)   # a run's four microphones too
    heard = SpeechRecognizer().transcribe(samples, rate)
    reply = manager.respond(heard.text, mood, confidence=heard.confidence)
    _print_heard(heard, reply, args.json, out)
    return 0


def _print_heard(heard: Any, reply: Any, as_json: bool, out: TextIO,
                 extra: dict[str, float] | None = None) -> None:
    """What the recogniser heard and the reply: a JSON object, or two lines or more."""
    if as_json:
        print(json.dumps({**(extra or {}), "heard": heard.text,
                          "confidence": round(heard.confidence, 3),
                          "snr_db": round(heard.snr_db, 1), **reply.to_dict()}), file=out,
              flush=True)
        return
    print(f"heard: {heard.text or '(no words)'} (confidence {heard.confidence:.2f}, "
          f"{heard.snr_db:.0f} dB over the noise)", file=out)
    _print_reply(reply, out)
    out.flush()


def _listen(args: argparse.Namespace, folder: Path, blocks: Iterable[Any], out: TextIO) -> int:
    """``chat --listen``: the session's dialogue, then each utterance heard in ``blocks``
    answered (:func:`listen_and_answer`)."""
    from dialogue.factory import chat_session, robot_mood

    manager, drives, personality = chat_session(args.scenario, DEFAULT_SCENARIO, args.weather,
                                                args.feed, folder)
    manager.context.mode = args.mode
    mood = args.mood or robot_mood(drives, personality)[0]
    if not args.json:
        print(f"Robot mood: {mood}. Listening to the default microphone: talk, and the robot "
              "answers when you stop; Ctrl-C leaves.", file=out, flush=True)
    return listen_and_answer(blocks, manager, mood, out, args.json)


def listen_and_answer(blocks: Iterable[Any], manager: Any, mood: str, out: TextIO,
                      as_json: bool = False, recognizer: Any = None, detector: Any = None) -> int:
    """Pass ``blocks`` (16 kHz int16, from a microphone or a file) through the voice-activity
    detector; give each utterance, as soon as it ends, to the recogniser and ``manager`` (as
    ``chat --audio`` does) and print what was heard and the reply. 0 at the end of the blocks
    or on Ctrl-C (SIGTERM is passed on)."""
    from dialogue.speech.listen import utterances
    from dialogue.speech.recognizer import SpeechRecognizer

    recognizer = recognizer or SpeechRecognizer()
    try:
        for utterance in utterances(blocks, detector):
            heard = recognizer.transcribe(utterance.samples)
            reply = manager.respond(heard.text, mood, confidence=heard.confidence)
            _print_heard(heard, reply, as_json, out, {"start_s": round(utterance.start_s, 2),
                                                      "end_s": round(utterance.end_s, 2)})
    except Terminated:
        raise
    except KeyboardInterrupt:   # Ctrl-C: goodbye
        print(file=out)
    return 0


def _readline(stdin: TextIO, out: TextIO) -> str:
    print("you> ", end="", file=out, flush=True)
    line = stdin.readline()
    if not line:
        raise EOFError
    return line


def run_eval(args: argparse.Namespace) -> int:
    """``companion eval dialogue``: routing accuracy on the held-out set and reply latency."""
    from dialogue.factory import shipped_chitchat
    from dialogue.intent import evaluate_routing, load_utterances
    from dialogue.manager import DialogueContext, DialogueManager
    from dialogue.qa.bot import QABot

    result = evaluate_routing(path=args.heldout)
    with tempfile.TemporaryDirectory(prefix="companion-eval-") as tmp:
        manager = DialogueManager(QABot.offline(out_dir=tmp), chitchat=shipped_chitchat())
        times = []
        for _, text in load_utterances(args.heldout):
            t0 = time.perf_counter()
            manager.respond(text, "positive", DialogueContext())
            times.append((time.perf_counter() - t0) * 1000)
    result["latency_ms_median"] = statistics.median(times)
    chat = chat_model_metrics()
    if args.json:
        keys = ("routing_accuracy", "latency_ms_median", "routing_ms_median", "n", "per_label",
                "misses")
        print(json.dumps({**{k: result[k] for k in keys}, **chat}))
        return 0
    ok = "meets" if result["routing_accuracy"] >= ROUTING_BAR else "BELOW"
    print(f"routing accuracy: {result['routing_accuracy']:.3f} on {result['n']} held-out "
          f"utterances ({ok} the bar of {ROUTING_BAR})")
    for label, acc in result["per_label"].items():
        print(f"  {label:<15} {acc:.3f}")
    print(f"reply latency: median {result['latency_ms_median']:.1f} ms per utterance "
          f"(routing alone {result['routing_ms_median']:.1f} ms)")
    for m in result["misses"]:
        print(f"  misrouted: {m['text']!r} -> {m['got']} (expected {m['expected']})")
    if chat:
        print(f"chit-chat perplexity on held-out pairs: {chat['chat_perplexity']:.1f} "
              f"(unigram baseline {chat['unigram_perplexity']:.1f}); distinct-1/2 "
              f"{chat['distinct_1']:.3f}/{chat['distinct_2']:.3f}")
    else:
        print("chit-chat perplexity: no chit-chat model (train one with `companion train chat`)")
    return 0


def run_eval_knowledge(args: argparse.Namespace) -> int:
    """``companion eval knowledge``: share of correct answers, against the bar."""
    from dialogue.knowledge_eval import KNOWLEDGE_BAR, QUESTIONS_FILE, evaluate_knowledge

    result = evaluate_knowledge(args.questions or QUESTIONS_FILE)
    if args.json:
        print(json.dumps(result))
        return 0
    for r in result["results"]:
        if r["mark"] != "correct":
            print(f"  {r['mark']:<10} {r['question']!r} -> {r['answer']!r}")
    ok = "meets" if result["accuracy"] >= KNOWLEDGE_BAR else "BELOW"
    print(f"knowledge: {result['accuracy']:.3f} correct on {result['n']} questions ({ok} the "
          f"bar of {KNOWLEDGE_BAR}); " + ", ".join(f"{k} {v}" for k, v in result["marks"].items()))
    for kind, acc in result["per_kind"].items():
        print(f"  {kind:<10} {acc:.3f}")
    print(f"reply latency: median {result['latency_ms_median']:.1f} ms, longest "
          f"{result['latency_ms_max']:.0f} ms (the first question builds the index of people)")
    return 0


def chat_model_metrics() -> dict[str, float]:
    """Held-out chit-chat figures of the shipped model (empty while none is shipped)."""
    from dialogue.chat.config import DEFAULT_CHAT_MODEL
    from dialogue.chat.training.cli import chat_metrics

    if not DEFAULT_CHAT_MODEL.is_file():
        return {}
    metrics = chat_metrics(DEFAULT_CHAT_MODEL)
    return {k: metrics[k] for k in ("chat_perplexity", "unigram_perplexity", "distinct_1",
                                    "distinct_2")}


def run_eval_conversation(args: argparse.Namespace) -> int:
    """Handler of ``companion eval conversation``."""
    from dialogue.conversation_eval import evaluate, print_report

    result = evaluate(args.lines, args.config, args.examples)
    print(json.dumps(result, indent=2) if args.json else print_report(result))
    return 0 if all(result["meets_bars"].values()) else 1

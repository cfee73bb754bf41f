"""The tablet and the live view in a real browser (headless Chromium through selenium;
`make setup` installs Debian's chromium and chromium-driver): every button answers with its
card, the pages fetch nothing from elsewhere, the live view updates during a short run, the
tablet speaks to the running robot, and the replay moves with its slider. Screenshots go to
$TABLET_SCREENSHOTS (default: the test's temporary folder)."""

from __future__ import annotations

import os
import shutil
import threading
from pathlib import Path

import pytest
from test_tablet import CARD_OF
from test_tablet_run import quiet_living_room

from app.run import RunOptions, run_scenario
from app.tablet.chat_link import ChatTablet
from app.tablet.config import KINDS, load_tablet_config
from app.tablet.replay import ReplayView
from app.tablet.run_link import RunTablet
from app.tablet.serve import TabletServer
from mind.personality import ACTIONS

ROOT = Path(__file__).resolve().parents[1]
CHROMIUM, DRIVER = shutil.which("chromium"), shutil.which("chromedriver")
WAIT_S = 60

if not (CHROMIUM and DRIVER):
    if os.environ.get("CI"):
        pytest.fail("chromium and chromedriver are missing: run `make setup`", pytrace=False)
    pytest.skip("chromium and chromedriver are missing: run `make setup`",
                allow_module_level=True)

from selenium import webdriver  # noqa: E402
from selenium.webdriver.common.by import By  # noqa: E402
from selenium.webdriver.common.keys import Keys  # noqa: E402
from selenium.webdriver.support.ui import WebDriverWait  # noqa: E402


@pytest.fixture(scope="module")
def shots(tmp_path_factory) -> Path:
    folder = Path(os.environ.get("TABLET_SCREENSHOTS") or tmp_path_factory.mktemp("shots"))
    folder.mkdir(parents=True, exist_ok=True)
    return folder


@pytest.fixture(scope="module")
def browser():
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for arg in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                "--window-size=1100,1300", "--disable-extensions", "--no-first-run"):
        options.add_argument(arg)
    driver = webdriver.Chrome(options=options, service=webdriver.ChromeService(DRIVER))
    yield driver
    driver.quit()


def wait(driver, condition, timeout: float = WAIT_S):
    return WebDriverWait(driver, timeout, poll_frequency=0.05).until(condition)


def only_local_resources(driver, base: str) -> None:
    """Everything the page fetched came from the app itself (or was a data: URL)."""
    names = driver.execute_script(
        "return performance.getEntriesByType('resource').map(e => e.name)")
    assert all(n.startswith(base) or n.startswith("data:") for n in names), names


def press(driver, kind: str) -> dict:
    """Press a conversation button; the shown reply once it has changed."""
    before = driver.find_element(By.TAG_NAME, "body").get_attribute("data-seq") or "0"
    driver.find_element(By.ID, f"btn-{kind}").click()
    wait(driver, lambda d: (d.find_element(By.TAG_NAME, "body").get_attribute("data-seq")
                            or "0") != before)
    return {"text": driver.find_element(By.ID, "reply-text").text,
            "route": driver.find_element(By.ID, "route").text,
            "card": driver.find_element(By.ID, "card").get_attribute("data-kind")}


def test_every_tablet_button_in_the_browser(browser, shots, tmp_path):
    tablet = ChatTablet.from_scenario(ROOT / "worlds" / "living_room.yaml",
                                      load_tablet_config(), tmp_path)
    with TabletServer(tablet, "127.0.0.1", 0) as server:
        base = f"http://127.0.0.1:{server.port}/"
        browser.get(base)
        wait(browser, lambda d: d.find_element(By.TAG_NAME, "body").get_attribute("data-ready"))
        for kind in KINDS:
            shown = press(browser, kind)
            assert shown["route"].startswith(kind) and shown["text"], shown
            assert shown["card"] == CARD_OF.get(kind, "none"), (kind, shown)
            if shown["card"] == "image":
                img = browser.find_element(By.CSS_SELECTOR, "#card img")
                wait(browser, lambda _, i=img: browser.execute_script(
                    "return arguments[0].complete && arguments[0].naturalWidth > 0", i))
            assert "Original:" in browser.find_element(By.ID, "card").text or kind in (
                "chitchat", "map", "photo")
            browser.save_screenshot(str(shots / f"tablet-{kind}.png"))
        browser.find_element(By.ID, "text").send_keys("What time is it in Tokyo?")
        shown = press(browser, "time")
        assert "Tokyo" in shown["text"] and shown["card"] == "clock"
        browser.find_element(By.ID, "fb-up").click()
        wait(browser, lambda d: d.find_element(By.ID, "fb-status").text)
        only_local_resources(browser, base)
    tablet.close()


@pytest.fixture(scope="module")
def live_run(browser, shots, tmp_path_factory):
    """A short run served with the tablet; the browser watches the live view, then speaks
    to the robot through the tablet page, while the run goes on in this thread."""
    out = tmp_path_factory.mktemp("browser-run") / "run"
    tablet = RunTablet(load_tablet_config())
    seen: dict = {}

    def watch(base: str) -> None:
        try:
            browser.get(base + "mind")
            wait(browser, lambda d: int(d.find_element(By.TAG_NAME, "body")
                                        .get_attribute("data-updates")) >= 1)
            seen["t0"] = float(browser.find_element(By.TAG_NAME, "body").get_attribute("data-t"))
            wait(browser, lambda d: int(d.find_element(By.TAG_NAME, "body")
                                        .get_attribute("data-updates")) >= 6)
            seen["t1"] = float(browser.find_element(By.TAG_NAME, "body").get_attribute("data-t"))
            seen["bars"] = len(browser.find_elements(By.CSS_SELECTOR, "#motivations .bar"))
            seen["tree"] = browser.find_element(By.ID, "tree").text
            seen["frame"] = browser.find_element(By.ID, "frame").get_attribute("src")[:30]
            browser.save_screenshot(str(shots / "mind-live.png"))
            browser.get(base)
            wait(browser, lambda d: d.find_element(By.TAG_NAME, "body")
                 .get_attribute("data-ready"))
            seen["reply"] = press(browser, "time")
            only_local_resources(browser, base)
        except Exception as exc:   # reported by the tests, not lost in this thread
            seen["error"] = repr(exc)

    with TabletServer(tablet, "127.0.0.1", 0) as server:
        watcher = threading.Thread(target=watch, args=(f"http://127.0.0.1:{server.port}/",))
        watcher.start()
        run_scenario(quiet_living_room(duration=240.0), out, RunOptions(tablet=tablet),
                     progress=False)
        watcher.join(timeout=WAIT_S)
    return out, seen


def test_the_live_view_updates_during_a_run(live_run):
    _, seen = live_run
    assert "error" not in seen, seen.get("error")
    assert seen["t1"] > seen["t0"] and seen["bars"] == 6
    assert "Sense" in seen["tree"] and seen["frame"].startswith("data:image/jpeg")


def test_the_tablet_speaks_to_the_running_robot(live_run):
    _, seen = live_run
    assert "error" not in seen, seen.get("error")
    assert seen["reply"]["route"].startswith("time") and seen["reply"]["card"] == "clock"


def test_the_replay_moves_with_its_slider(live_run, browser, shots):
    out, _ = live_run
    with TabletServer(ReplayView(out, load_tablet_config()), "127.0.0.1", 0) as server:
        browser.get(f"http://127.0.0.1:{server.port}/mind")
        body = browser.find_element(By.TAG_NAME, "body")
        wait(browser, lambda _: body.get_attribute("data-updates") != "0")
        start_t, start_frame = body.get_attribute("data-t"), browser.find_element(
            By.ID, "frame").get_attribute("src")
        slider = browser.find_element(By.ID, "slider")
        slider.send_keys(Keys.END)
        wait(browser, lambda _: float(body.get_attribute("data-t")) > 200)
        assert float(body.get_attribute("data-t")) > float(start_t)
        wait(browser, lambda _: browser.find_element(By.ID, "frame").get_attribute("src")
             != start_frame)
        for _ in range(30):
            slider.send_keys(Keys.ARROW_LEFT)
        wait(browser, lambda _: 150 < float(body.get_attribute("data-t")) < 235)
        assert browser.find_element(By.ID, "action").text in ACTIONS
        browser.save_screenshot(str(shots / "mind-replay.png"))

"""The HTML report of the sample in a real headless browser (Debian's chromium through
chromedriver): the page loads without a console or resource error, every diagram is an image
that loaded, and each diagram's region of the screenshot is not blank. The screenshot of the
top of the page is kept as a CI artefact in build/artifacts/report.png."""

from __future__ import annotations

import io
import shutil
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from earl_m2t.cli.app import main

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
ARTEFACT = ROOT / "build" / "artifacts" / "report.png"
CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
CHROMEDRIVER = shutil.which("chromedriver") or "/usr/bin/chromedriver"

selenium = pytest.importorskip("selenium", reason="selenium (the test extras) is not installed")
Image = pytest.importorskip("PIL.Image", reason="Pillow (the test extras) is not installed")

pytestmark = [
    pytest.mark.skipif(shutil.which("dot") is None, reason="Graphviz dot is missing (./dev installs graphviz)"),
    pytest.mark.skipif(not (Path(CHROMIUM).is_file() and Path(CHROMEDRIVER).is_file()),
                       reason="chromium and chromium-driver are missing (./dev test installs them)"),
]

# the fraction of a diagram's pixels that must differ from the white background
MIN_INK = 0.01


@pytest.fixture(scope="module")
def report(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("report")
    assert main(["report", str(SAMPLE), "-o", str(out)]) == 0
    return out


@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-dev-shm-usage", "--window-size=1400,1000", "--hide-scrollbars",
                 "--force-device-scale-factor=1"):
        options.add_argument(flag)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(service=Service(executable_path=CHROMEDRIVER), options=options)
    driver.set_page_load_timeout(60)
    try:
        yield driver
    finally:
        driver.quit()


def load(driver: Any, page: Path) -> list[str]:
    """Open a page and wait until it and its images are loaded; the console's errors."""
    from selenium.webdriver.support.ui import WebDriverWait

    driver.get_log("browser")  # forget what an earlier page said
    driver.get(page.as_uri())
    WebDriverWait(driver, 30).until(lambda d: d.execute_script(
        "return document.readyState === 'complete' && Array.from(document.images).every(i => i.complete)"))
    return [f"{entry['level']}: {entry['message']}" for entry in driver.get_log("browser")
            if entry["level"] in ("SEVERE", "WARNING")]


def broken_images(driver: Any) -> list[str]:
    return list(driver.execute_script(
        "return Array.from(document.images).filter(i => !(i.naturalWidth > 0)).map(i => i.getAttribute('src'))"))


def ink(png: bytes, box: dict[str, float]) -> float:
    """The fraction of the pixels in ``box`` (CSS pixels) that are not near-white."""
    image = Image.open(io.BytesIO(png)).convert("RGB")
    left, top = max(int(box["left"]), 0), max(int(box["top"]), 0)
    right, bottom = min(int(box["right"]), image.width), min(int(box["bottom"]), image.height)
    assert right - left > 20 and bottom - top > 20, f"diagram region too small: {box}"
    region = image.crop((left, top, right, bottom)).convert("L")
    dark = sum(region.histogram()[:200])  # grey levels below 200: lines, text, arrows
    return dark / (region.width * region.height)


def test_the_report_loads_without_errors_and_every_diagram_is_visible(report: Path, browser: Any) -> None:
    errors = load(browser, report / "index.html")
    assert errors == []
    assert browser.title == "PickAndPlace: EARL specification"
    assert broken_images(browser) == []
    ARTEFACT.parent.mkdir(parents=True, exist_ok=True)
    ARTEFACT.write_bytes(browser.get_screenshot_as_png())
    count = browser.execute_script("return document.querySelectorAll('figure img').length")
    assert count == len(list((report / "diagrams").glob("*.svg"))) == 22
    for index in range(count):
        box = browser.execute_script(
            "const img = document.querySelectorAll('figure img')[arguments[0]];"
            "img.scrollIntoView({block: 'start'});"
            "const r = img.getBoundingClientRect();"
            "return {left: r.left, top: r.top, right: r.right, bottom: Math.min(r.bottom, window.innerHeight),"
            " src: img.getAttribute('src'), svg: img.currentSrc.endsWith('.svg')};", index)
        assert box["svg"], box
        assert ink(browser.get_screenshot_as_png(), box) > MIN_INK, f"{box['src']} looks blank"


def test_the_anchors_of_elements_exist_in_the_page(report: Path, browser: Any) -> None:
    load(browser, report / "index.html")
    for anchor in ("manip-a", "manip-a-cs", "manip-a-motorControllerK-ve", "manip-a-motorController3-ve",
                   "manip-a-cs-fsm-idle-jointMove-t", "manip-a-cs-idle-bb", "manip-a-cs-calculatePosition-pf",
                   "manip-a-cs-windingCurrentK-m", "manip-a-cs-emergencyStop-pp", "report-findings"):
        assert browser.execute_script("return document.getElementById(arguments[0]) !== null", anchor), anchor


def test_a_missing_diagram_is_caught(report: Path, browser: Any, tmp_path: Path) -> None:
    broken = tmp_path / "broken"
    shutil.copytree(report, broken)
    (broken / "diagrams" / "system.svg").unlink()
    errors = load(browser, broken / "index.html")
    assert any("ERR_FILE_NOT_FOUND" in error for error in errors), errors
    assert broken_images(browser) == ["diagrams/system.svg"]


def test_a_blank_region_is_caught() -> None:
    blank = io.BytesIO()
    Image.new("RGB", (200, 100), "white").save(blank, format="PNG")
    assert ink(blank.getvalue(), {"left": 0, "top": 0, "right": 200, "bottom": 100}) == 0

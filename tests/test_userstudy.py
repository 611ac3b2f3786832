"""The user-study kit (capframe.userstudy): the questionnaire made from a results tree holds no
method name and a key that maps every image to its render; the importer's table on hand-written
answers and its rejections; and a click-through of the page in headless Chromium whose CSV the
importer reads back into the table the scripted answers imply."""

from __future__ import annotations

import functools
import http.server
import json
import math
import re
import shutil
import threading
from pathlib import Path

import cv2
import numpy as np
import pandas as pd
import pytest
from PIL import Image

from capframe.cli import main
from capframe.errors import InputError
from capframe.userstudy import import_answers, make_questionnaire
from capframe.userstudy.key import ANSWER_COLUMNS, Group, Key, questionnaire_id, read_key

CHROMIUM = Path("/usr/bin/chromium")
# As the machines' notes give them: no sandbox as root, and nothing that reaches for a network.
CHROMIUM_ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
# Where the workflow puts each kind of method's results (capframe.userstudy.questionnaire.method_folder).
FOLDERS = {"capframe": "refine/capframe", "oracle": "refine/oracle", "svs": "baselines/svs", "retrieve": "retrieved"}


def fake_run(root: Path, methods=tuple(FOLDERS), scenes=("desk", "room"), per_scene=4) -> Path:
    """A results tree as a finished run leaves it, with a distinct drawn render (a disc whose
    colour and place depend on method and instruction) per method and instruction."""
    results = root / "results"
    for s, scene in enumerate(scenes):
        entries = {
            f"{scene}-{i:03d}": {"scene": scene, "text": f"a close-up of the mug number {s * 10 + i}"} for i in range(per_scene)
        }
        folder = results / "instructions" / scene
        folder.mkdir(parents=True)
        (folder / "constraints.json").write_text(json.dumps(entries))
        for m, method in enumerate(methods):
            for i, instruction in enumerate(entries):
                image = np.full((48, 64, 3), 30 * m, np.uint8)
                cv2.circle(image, (8 + 6 * i, 10 + 8 * s), 6, (255 - 40 * m, 40 * i, 90 * s), -1)
                out = results / FOLDERS.get(method, f"refine/{method}") / scene / instruction
                out.mkdir(parents=True)
                cv2.imwrite(str(out / "render.png"), image)
    return results


def pixels(path) -> np.ndarray:
    with Image.open(path) as image:
        return np.asarray(image.convert("RGB"))


# --- making the questionnaire ------------------------------------------------------------------


def test_the_site_shows_each_render_under_a_hashed_name_and_the_key_stays_outside_it(tmp_path):
    results = fake_run(tmp_path)
    out = tmp_path / "study"
    key = make_questionnaire(results, ["capframe", "oracle", "svs"], out, groups=6, seed=3)
    assert sorted(p.name for p in out.iterdir()) == ["key.json", "site"]
    assert not list((out / "site").rglob("*.json"))
    assert read_key(out / "key.json") == key
    assert len(key.groups) == 6 and len(list((out / "site" / "img").iterdir())) == 18
    html = (out / "site" / "index.html").read_text()
    for group in key.groups:
        assert group.text in html
        assert list(group.methods) == ["A", "B", "C"] and sorted(group.methods.values()) == ["capframe", "oracle", "svs"]
        for label, method in group.methods.items():
            # The key's method for the label is the one whose render the page shows under it.
            render = results / FOLDERS[method] / group.scene / group.instruction / "render.png"
            assert group.sources[label] == str(render)
            assert np.array_equal(pixels(out / "site" / group.images[label]), pixels(render))
            assert f'src="{group.images[label]}" alt="Image {label}"' in html


def test_the_site_holds_no_method_name(tmp_path):
    methods = ["capframe", "oracle", "svs", "retrieve", "capframe-top3"]
    results = fake_run(tmp_path, methods=methods)
    out = tmp_path / "study"
    make_questionnaire(results, methods, out, groups=8, seed=1)
    files = [p for p in (out / "site").rglob("*")]
    assert len(files) == 1 + 1 + 8 * 3  # index.html, img/, the images
    for method in methods:
        for path in files:
            assert method not in path.relative_to(out / "site").as_posix().lower()
            if path.is_file():
                assert method.encode() not in path.read_bytes().lower(), (method, path)
    # The key does name them: the check above would see a leak.
    assert all(m in (out / "key.json").read_text() for m in methods)


def test_the_draw_is_seeded_over_instructions_with_every_render_and_balances_the_methods(tmp_path):
    methods = ["capframe", "oracle", "svs", "retrieve", "capframe-top3"]
    results = fake_run(tmp_path, methods=methods, per_scene=8)
    shutil.rmtree(results / "retrieved" / "desk" / "desk-002")  # one method lacks this render
    keys = [
        make_questionnaire(results, methods, tmp_path / f"study{i}", groups=12, seed=seed) for i, seed in enumerate((5, 5, 6))
    ]
    same = [[g.to_dict() | {"images": None} for g in k.groups] for k in keys]
    assert same[0] == same[1] and same[0] != same[2]
    assert keys[0].questionnaire != keys[1].questionnaire  # a fresh nonce: answers to two builds never mix
    for key in keys:
        assert "desk-002" not in {g.instruction for g in key.groups}
        assert len({(g.scene, g.instruction) for g in key.groups}) == 12
        counts = [sum(m in g.methods.values() for g in key.groups) for m in methods]
        assert sum(counts) == 36 and max(counts) - min(counts) <= 1
        # Orders vary from group to group (the first label is not always the same method).
        assert len({g.methods["A"] for g in key.groups}) > 1


@pytest.mark.parametrize(
    "methods, options, message",
    [
        (["capframe", "oracle", "ivs"], {}, "no results for 'ivs'"),
        (["capframe", "oracle", "svs"], {"groups": 9}, "--groups 9 asks for more; expected 8 or fewer"),
        (["capframe", "oracle"], {"groups": 2}, "--per-group 3: expected 2 to 2"),
        (["capframe", "oracle", "oracle"], {"groups": 2}, "expected two or more distinct"),
        (["capframe"], {"per_group": 1}, "expected two or more distinct"),
        (["capframe", "oracle", "group"], {"groups": 2}, "would hold the method name 'group'"),
    ],
)
def test_make_refuses_bad_choices_and_writes_nothing(tmp_path, methods, options, message):
    results = fake_run(tmp_path, methods=("capframe", "oracle", "svs", "group"))
    with pytest.raises(InputError, match=re.escape(message)) as err:
        make_questionnaire(results, methods, tmp_path / "study", **options)
    assert "\n" not in str(err.value)
    assert not (tmp_path / "study").exists() and not list(tmp_path.glob(".study*"))


def test_an_instruction_that_names_a_method_is_not_drawn(tmp_path):
    results = fake_run(tmp_path)
    path = results / "instructions" / "desk" / "constraints.json"
    entries = json.loads(path.read_text())
    entries["desk-001"]["text"] = "the Oracle's favourite mug"
    path.write_text(json.dumps(entries))
    key = make_questionnaire(results, ["capframe", "oracle", "svs"], tmp_path / "study", groups=7)
    assert "desk-001" not in {g.instruction for g in key.groups}


# --- importing answers -------------------------------------------------------------------------

METHODS = ("capframe", "oracle", "svs", "ivs", "splatraj")


def hand_key(path: Path) -> Key:
    """Two groups of three of the five methods (splatraj never shown), written to ``path``."""
    images, sources = {k: f"img/{k}.png" for k in "ABC"}, dict.fromkeys("ABC", "render.png")
    groups = (
        Group(1, "desk", "desk-000", "a mug", {"A": "capframe", "B": "oracle", "C": "svs"}, images, sources),
        Group(2, "room", "room-004", "a chair", {"A": "ivs", "B": "capframe", "C": "oracle"}, images, sources),
    )
    draft = Key("", "0" * 32, 0, METHODS, groups)
    key = Key(questionnaire_id(draft.content()), draft.nonce, 0, METHODS, groups)
    key.write(path)
    return key


def answers_csv(key: Key, participant: str, rows: list[tuple]) -> str:
    """CSV text of ``(group, image, rating, best)`` rows, as the page writes it."""
    lines = [",".join(ANSWER_COLUMNS)]
    quoted = f'"{participant}"' if "," in participant else participant
    lines += [",".join(map(str, (key.questionnaire, quoted, *row))) for row in rows]
    return "\r\n".join(lines) + "\r\n"


# Participant 1 answers both groups, participant 2 (an id with a comma, quoted) only group 1.
P1 = [(1, "A", 5, 1), (1, "B", 4, 0), (1, "C", 1, 0), (2, "A", 2, 0), (2, "B", 4, 1), (2, "C", 2, 0)]
P2 = [(1, "A", 3, 0), (1, "B", 5, 1), (1, "C", 2, 0)]


def test_the_table_of_hand_written_answers(tmp_path):
    key = hand_key(tmp_path / "key.json")
    (tmp_path / "p1.csv").write_text(answers_csv(key, "p1", P1))
    (tmp_path / "p2.csv").write_text(answers_csv(key, "Doe, J", P2))
    out = tmp_path / "tables" / "userstudy.csv"
    rc = main(
        [
            "userstudy",
            "import",
            "--key",
            str(tmp_path / "key.json"),
            str(tmp_path / "p1.csv"),
            str(tmp_path / "p2.csv"),
            "-o",
            str(out),
        ]
    )
    assert rc == 0
    table = pd.read_csv(out)
    assert list(table.columns) == ["method", "rating_mean", "rating_n", "preference_share"]
    assert list(table["method"]) == list(METHODS)
    rows = {r.method: (r.rating_mean, r.rating_n, r.preference_share) for r in table.itertuples()}
    # capframe: ratings 5 (p1 g1 A), 4 (p1 g2 B), 3 (p2 g1 A); picked in 2 of the 3 answered groups.
    assert rows["capframe"] == pytest.approx((4.0, 3, 2 / 3))
    # oracle: 4 (p1 g1 B), 2 (p1 g2 C), 5 (p2 g1 B); picked by p2 in group 1.
    assert rows["oracle"] == pytest.approx((11 / 3, 3, 1 / 3))
    # svs: group 1 only (twice): 1 and 2, never picked; ivs: group 2 only (once): 2.
    assert rows["svs"] == pytest.approx((1.5, 2, 0.0))
    assert rows["ivs"] == pytest.approx((2.0, 1, 0.0))
    assert rows["splatraj"][1] == 0 and math.isnan(rows["splatraj"][0]) and math.isnan(rows["splatraj"][2])


def _replace(rows, index, **change):
    fields = dict(zip(("group", "image", "rating", "best"), rows[index]))
    return [*rows[:index], tuple({**fields, **change}.values()), *rows[index + 1 :]]


@pytest.mark.parametrize(
    "rows, text, message",
    [
        (_replace(P1, 1, group=3), None, "line 3: group is '3': unknown group"),
        (_replace(P1, 4, group="x"), None, "line 6: group is 'x': unknown group"),
        (_replace(P1, 2, rating=6), None, "line 4: rating is '6'; expected a whole number from 1 to 5"),
        (_replace(P1, 0, rating=0), None, "line 2: rating is '0'"),
        (_replace(P1, 0, rating=4.5), None, "line 2: rating is '4.5'"),
        (_replace(P1, 3, best=2), None, "line 5: best is '2'"),
        (_replace(P1, 3, image="D"), None, "line 5: image is 'D'; group 2 shows images A, B, C"),
        ([*P1, P1[2]], None, "line 8: image: duplicated answer: participant 'p1', group 1, image C was already answered"),
        (P1[:2] + P1[3:], None, "line 2: image: participant 'p1' answered images ['A', 'B'] of group 1"),
        (_replace(P1, 5, best=1), None, "line 5: best: participant 'p1' picked 2 images ['B', 'C'] as group 2's best"),
        (_replace(P1, 4, best=0), None, "line 5: best: participant 'p1' picked 0 images"),
        ([], None, "holds no answers"),
        (P1, "questionnaire,participant,group,image,rating\n", "line 1: header is"),
        (P1, "other", "line 2: questionnaire is 'ffffffffffffffff', but"),
        (P1, "short", "line 3: has 5 fields; expected 6"),
        (P1, "nobody", "line 2: participant is empty"),
    ],
)
def test_the_importer_refuses_a_bad_row_naming_file_line_and_field(tmp_path, rows, text, message):
    key = hand_key(tmp_path / "key.json")
    content = answers_csv(key, "p1", rows)
    if text == "other":
        content = content.replace(key.questionnaire, "f" * 16)
    elif text == "short":
        content = content.replace(",4,0\r\n", ",4\r\n", 1)
    elif text == "nobody":
        content = content.replace(",p1,", ",,")
    elif text is not None:
        content = text + content.split("\n", 1)[1]
    (tmp_path / "bad.csv").write_text(content)
    out = tmp_path / "userstudy.csv"
    with pytest.raises(InputError) as err:
        import_answers(tmp_path / "key.json", [tmp_path / "bad.csv"], out)
    assert str(err.value).startswith(f"{tmp_path / 'bad.csv'}: {message}")
    assert "\n" not in str(err.value) and not out.exists()


def test_the_importer_refuses_a_participant_answering_twice_and_an_edited_key(tmp_path):
    key = hand_key(tmp_path / "key.json")
    for name in ("a.csv", "b.csv"):
        (tmp_path / name).write_text(answers_csv(key, "p1", P1))
    with pytest.raises(InputError, match=r"b\.csv: line 2: image: duplicated answer: .* \(.*a\.csv line 2\)"):
        import_answers(tmp_path / "key.json", [tmp_path / "a.csv", tmp_path / "b.csv"], tmp_path / "t.csv")
    data = json.loads((tmp_path / "key.json").read_text())
    data["groups"][0]["methods"] = {"A": "oracle", "B": "capframe", "C": "svs"}
    (tmp_path / "key.json").write_text(json.dumps(data))
    with pytest.raises(InputError, match=r"key\.json: questionnaire is '[0-9a-f]{16}' but the key's content hashes to"):
        import_answers(tmp_path / "key.json", [tmp_path / "a.csv"], tmp_path / "t.csv")


# --- the page in a browser ---------------------------------------------------------------------


def scripted_rating(group: int, label: str) -> int:
    return 1 + (3 * group + ord(label)) % 5


def scripted_best(group: int, labels: list[str]) -> str:
    return labels[(group * 2) % len(labels)]


@pytest.fixture
def served(tmp_path):
    """A questionnaire of the fake run served over HTTP on 127.0.0.1: (base URL, key, folder)."""
    results = fake_run(tmp_path)
    out = tmp_path / "study"
    command = ["userstudy", "make", "--results", str(results), "--methods", "capframe,oracle,svs,retrieve", "--groups", "5"]
    assert main([*command, "--seed", "2", "-o", str(out)]) == 0
    key = read_key(out / "key.json")
    handler = functools.partial(http.server.SimpleHTTPRequestHandler, directory=str(out / "site"))
    handler.log_message = lambda *args: None  # no request lines in the test's output
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{server.server_address[1]}/index.html", key, out
    server.shutdown()
    server.server_close()


@pytest.mark.skipif(
    not CHROMIUM.exists(), reason=f"{CHROMIUM} is absent (Debian's chromium package; make test installs it as root)"
)
def test_a_scripted_click_through_in_headless_chromium_imports_to_the_implied_table(served, tmp_path):
    from playwright.sync_api import sync_playwright

    url, key, out = served
    downloads = []
    with sync_playwright() as p:
        # Playwright gives the browser a fresh, empty profile (--user-data-dir) of its own.
        browser = p.chromium.launch(executable_path=str(CHROMIUM), args=CHROMIUM_ARGS)
        try:
            page = browser.new_page(accept_downloads=True)
            page.on("download", lambda download: downloads.append(download))
            page.goto(url)
            assert page.evaluate("Array.from(document.images).every(i => i.complete && i.naturalWidth === 64)")
            assert page.locator("section.group").count() == len(key.groups)

            page.click("#download")
            assert "participant id" in page.text_content("#status")
            page.fill("#participant", "P-07")
            for group in key.groups:
                labels = list(group.methods)
                for label in labels:
                    if (group.number, label) != (4, "B"):
                        page.check(f'input[name="rating-{group.number}-{label}"][value="{scripted_rating(group.number, label)}"]')
                if group.number != 2:
                    page.check(f'input[name="best-{group.number}"][value="{scripted_best(group.number, labels)}"]')
            page.click("#download")
            status = page.text_content("#status")
            assert "Missing: group 2 (best image); group 4 (rating of image B)." in status, status
            assert page.locator("section.group.missing").count() == 2 and not downloads

            page.check(f'input[name="rating-4-B"][value="{scripted_rating(4, "B")}"]')
            page.check(f'input[name="best-2"][value="{scripted_best(2, list(key.group(2).methods))}"]')
            with page.expect_download() as info:
                page.click("#download")
            download = info.value
            assert download.suggested_filename == f"userstudy-P-07-{key.questionnaire}.csv"
            answers = tmp_path / "answers" / download.suggested_filename
            download.save_as(answers)
            assert "saved as" in page.text_content("#status") and page.locator("section.group.missing").count() == 0
        finally:
            browser.close()

    table_path = tmp_path / "tables" / "userstudy.csv"
    assert main(["userstudy", "import", "--key", str(out / "key.json"), str(answers), "-o", str(table_path)]) == 0
    table = pd.read_csv(table_path).set_index("method")
    # What the scripted clicks imply, from the key alone.
    ratings, shown, picked = {m: [] for m in key.methods}, dict.fromkeys(key.methods, 0), dict.fromkeys(key.methods, 0)
    for group in key.groups:
        best = scripted_best(group.number, list(group.methods))
        for label, method in group.methods.items():
            ratings[method].append(scripted_rating(group.number, label))
            shown[method] += 1
            picked[method] += label == best
    for method in key.methods:
        assert table.loc[method, "rating_n"] == len(ratings[method])
        assert table.loc[method, "rating_mean"] == pytest.approx(np.mean(ratings[method]))
        assert table.loc[method, "preference_share"] == pytest.approx(picked[method] / shown[method])


def test_the_import_verb_prints_a_refusal_as_one_line_and_writes_nothing(tmp_path, capsys):
    key = hand_key(tmp_path / "key.json")
    (tmp_path / "p1.csv").write_text(answers_csv(key, "p1", _replace(P1, 2, rating=9)))
    out = tmp_path / "userstudy.csv"
    assert main(["userstudy", "import", "--key", str(tmp_path / "key.json"), str(tmp_path / "p1.csv"), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err == f"capframe: error: {tmp_path / 'p1.csv'}: line 4: rating is '9'; expected a whole number from 1 to 5\n"
    assert not out.exists()

"""The questionnaire's page: one static HTML file with its style and script inline (no network).

What the participant sees: a participant-id field; per group, the instruction and its images
labelled A, B, ... each with a 1-5 rating, then "which image fits the instruction best?"; a
"Download answers" button that checks that everything is answered (else names what is missing,
in the page) and saves ``userstudy-<participant>-<questionnaire>.csv`` with the columns of
:data:`~capframe.userstudy.key.ANSWER_COLUMNS`. Only labels, image paths and the questionnaire id
reach the page; the methods stay in the key.
"""

from __future__ import annotations

import json
from html import escape

from .key import ANSWER_COLUMNS, RATINGS, Group, Key

_STYLE = """
body { font-family: system-ui, sans-serif; max-width: 70rem; margin: 1rem auto; padding: 0 1rem; line-height: 1.4; }
section.group { border: 1px solid #bbb; border-radius: 6px; padding: 0.5rem 1rem 1rem; margin: 1rem 0; }
section.group.missing { border: 2px solid #c00; }
blockquote { font-size: 1.15rem; margin: 0.5rem 0 1rem; padding-left: 0.8rem; border-left: 4px solid #888; }
.images { display: flex; flex-wrap: wrap; gap: 1rem; }
figure { margin: 0; flex: 1 1 18rem; }
figure img { width: 100%; height: auto; display: block; border: 1px solid #ddd; }
figcaption { font-weight: bold; margin: 0.3rem 0; }
fieldset { border: none; padding: 0; margin: 0.3rem 0; }
label { margin-right: 0.6rem; white-space: nowrap; }
#status { font-weight: bold; }
#status.error { color: #c00; }
button { font-size: 1.1rem; padding: 0.4rem 1.2rem; }
"""

# Reads the answers from the form and saves them as CSV. The columns and the ratings are
# filled in from ANSWER_COLUMNS and RATINGS by render_page, so the importer and the page agree.
_SCRIPT = """
(function () {
  "use strict";
  var COLUMNS = __COLUMNS__;
  var form = document.getElementById("study");
  var status = document.getElementById("status");
  var questionnaire = form.dataset.questionnaire;

  function picked(name) {
    var input = form.querySelector('input[name="' + name + '"]:checked');
    return input ? input.value : null;
  }

  function csvField(value) {
    value = String(value);
    return /[",\\r\\n]/.test(value) ? '"' + value.replace(/"/g, '""') + '"' : value;
  }

  function answers(participant) {
    var rows = [], missing = [];
    form.querySelectorAll("section.group").forEach(function (section) {
      var group = section.dataset.group, labels = section.dataset.images.split(","), lacks = [];
      var best = picked("best-" + group);
      labels.forEach(function (label) {
        var rating = picked("rating-" + group + "-" + label);
        if (rating === null) { lacks.push("rating of image " + label); }
        rows.push([questionnaire, participant, group, label, rating, label === best ? 1 : 0]);
      });
      if (best === null) { lacks.push("best image"); }
      section.classList.toggle("missing", lacks.length > 0);
      if (lacks.length > 0) {
        missing.push("group " + group + " (" + lacks.join(", ") + ")");
      }
    });
    return {rows: rows, missing: missing};
  }

  function report(message, isError) {
    status.textContent = message;
    status.className = isError ? "error" : "";
  }

  document.getElementById("download").addEventListener("click", function () {
    var participant = document.getElementById("participant").value.trim();
    var result = answers(participant);
    if (!participant) {
      report("Please enter your participant id at the top of the page before downloading.", true);
      document.getElementById("participant").focus();
      return;
    }
    if (result.missing.length > 0) {
      report("Please answer every group before downloading (outlined in red). Missing: " + result.missing.join("; ") + ".", true);
      return;
    }
    var lines = [COLUMNS.join(",")].concat(result.rows.map(function (row) { return row.map(csvField).join(","); }));
    var blob = new Blob([lines.join("\\r\\n") + "\\r\\n"], {type: "text/csv"});
    var name = "userstudy-" + participant.replace(/[^A-Za-z0-9_-]+/g, "_") + "-" + questionnaire + ".csv";
    var link = document.createElement("a");
    link.href = URL.createObjectURL(blob);
    link.download = name;
    document.body.appendChild(link);
    link.click();
    link.remove();
    setTimeout(function () { URL.revokeObjectURL(link.href); }, 1000);
    report("Your answers were saved as " + name + ". Please send that file to the study's organiser. Thank you!", false);
  });
})();
"""


def render_page(key: Key) -> str:
    """The questionnaire page of ``key`` as HTML text."""
    groups = "\n".join(_group_html(group, len(key.groups)) for group in key.groups)
    script = _SCRIPT.replace("__COLUMNS__", json.dumps(list(ANSWER_COLUMNS)))
    return f"""<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>Camera viewpoint study</title>
<style>{_STYLE}</style>
</head>
<body>
<h1>Camera viewpoint study</h1>
<p>Each of the {len(key.groups)} groups below gives a photographer's instruction and
{len(key.groups[0].methods)} images. Rate how well each image's content matches the instruction,
from 1 (very poor match) to 5 (excellent match), then pick the image that matches it best overall.
Judge only the match between the image and the text: disregard visual artifacts that have nothing
to do with where the camera is (blur, holes, stray specks). When every group is answered, press
<em>Download answers</em> at the bottom and send the file it saves.</p>
<form id="study" data-questionnaire="{escape(key.questionnaire)}" onsubmit="return false">
<p><label for="participant">Participant id:</label> <input id="participant" name="participant" required></p>
{groups}
<p><button type="button" id="download">Download answers</button></p>
<p id="status" role="alert"></p>
</form>
<script>{script}</script>
</body>
</html>
"""


def _group_html(group: Group, total: int) -> str:
    """One group's section: the instruction, each image with its ratings, the best pick."""
    g = group.number
    figures = []
    for label, image in group.images.items():
        ratings = "".join(f'<label><input type="radio" name="rating-{g}-{label}" value="{r}"> {r}</label>' for r in RATINGS)
        figures.append(
            f'<figure><img src="{escape(image)}" alt="Image {label}"><figcaption>Image {label}</figcaption>'
            f"<fieldset><legend>How well does image {label} match the instruction? (1 = very poor match, "
            f"5 = excellent match)</legend>{ratings}</fieldset></figure>"
        )
    best = "".join(f'<label><input type="radio" name="best-{g}" value="{label}"> {label}</label>' for label in group.images)
    return (
        f'<section class="group" id="group-{g}" data-group="{g}" data-images="{",".join(group.images)}">'
        f"<h2>Group {g} of {total}</h2><blockquote>{escape(group.text)}</blockquote>"
        f'<div class="images">{"".join(figures)}</div>'
        f"<fieldset><legend>Which image matches the instruction best?</legend>{best}</fieldset></section>"
    )

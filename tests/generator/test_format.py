"""Stage 6 (format): deterministic whitespace."""
from __future__ import annotations

from generator.format import format_source


def test_trailing_spaces_and_blank_runs_are_removed():
    assert format_source("a  \n\n\n\nb\t\n") == "a\n\nb\n"


def test_exactly_one_final_newline():
    assert format_source("a") == "a\n"
    assert format_source("a\n\n\n") == "a\n"


def test_formatting_is_idempotent():
    text = "x = 1;  \n\n\n  y = 2;\n\n"
    assert format_source(format_source(text)) == format_source(text)

"""The sliders' labels print their symbols as people write them (μₛ, x̄, x₀), the same as
the glossary, the readout and the pin labels (app.teach.glossary)."""

from __future__ import annotations

import unicodedata

import pytest

from app.compare import LABEL_NAMES
from app.control_specs import SI_SLIDERS, SLIDERS
from app.readout import printed
from app.teach.glossary import BETAS, PLAIN, SLIDER_SYMBOLS, SUBSCRIPTS, subscripted

#: The ASCII spellings the labels had ("static friction mu_s", "clearance x_bar", ...).
ASCII_MATH = ("mu_", "x_bar", "u_s", "x0", "x'0", "beta_")
LABELS = {name: label for name, (label, *_) in {**SLIDERS, **SI_SLIDERS}.items()}


@pytest.mark.parametrize("name", sorted(LABELS))
def test_no_label_spells_its_symbol_in_ascii(name):
    assert not any(text in LABELS[name] for text in ASCII_MATH), LABELS[name]


@pytest.mark.parametrize("name", sorted(SLIDER_SYMBOLS))
def test_a_slider_names_its_symbol_as_the_glossary_prints_it(name):
    key = SLIDER_SYMBOLS[name]
    symbols = BETAS if key == "beta" else (PLAIN[key],)
    assert any(symbol in LABELS[name] for symbol in symbols), (LABELS[name], symbols)


def test_the_readout_and_the_pin_labels_print_the_glossary_s_symbols():
    for ascii_text, key in (("mu_s", "mu_s"), ("mu_k", "mu_k"), ("x_bar", "x_bar")):
        assert printed(ascii_text) == PLAIN[key]
    assert LABEL_NAMES["mu_s"] == (PLAIN["mu_s"],) * 2 and LABEL_NAMES["x0"][0] == PLAIN["x0"]
    assert LABEL_NAMES["clearance"][0] in LABELS["clearance"]


def test_unicode_s_subscripts_are_the_letters_they_stand_for():
    """The independent reference: Unicode's own name of each character."""
    digits = "ZERO ONE TWO THREE FOUR FIVE SIX SEVEN EIGHT NINE".split()
    for plain, sub in SUBSCRIPTS.items():
        name = unicodedata.name(sub)
        expected = (f"SUBSCRIPT {digits[int(plain)]}" if plain.isdigit()
                    else f"LATIN SUBSCRIPT SMALL LETTER {plain.upper()}")
        assert name == expected, (plain, name)


def test_a_subscript_unicode_lacks_falls_back_alike_for_its_whole_family():
    """Unicode has no subscript c, d or N: k_c0 and k_e0 read alike (not k_c0 beside
    kₑ₀), and so do β_c and β_e; μₛ and μₖ both have theirs."""
    assert (PLAIN["k_c0"], PLAIN["k_e0"]) == ("k_c0", "k_e0")
    assert BETAS == ("β_c", "β_e")
    assert (PLAIN["mu_s"], PLAIN["mu_k"]) == ("μₛ", "μₖ")
    assert (PLAIN["x0"], PLAIN["v0"], PLAIN["u_s"]) == ("x₀", "x₀'", "uₛ")
    assert subscripted("v", "dr") == "v_dr" and subscripted("F", "N") == "F_N"
    assert subscripted("k", "e0") == "kₑ₀"  # alone, e and 0 have subscripts


def test_the_presentation_strip_labels_its_sliders_as_the_sidebar_does():
    """The strip's short labels are the sidebar sliders' symbols (they read "x_bar" and
    "mu_s" beside a sidebar showing x̄ and μₛ)."""
    from app.present_strip import SYMBOLS

    for name, symbol in SYMBOLS.items():
        assert not any(text in symbol for text in ASCII_MATH), symbol
        assert symbol in LABELS[name], (symbol, LABELS[name])

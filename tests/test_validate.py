"""cagd._validate: the structural checks made before OCCT parses a file (no OCCT
needed here: every case is a hand-made file and the expected verdict)."""
import pytest

from cagd import CagdError
from cagd._validate import MAX_NESTING, check_name, validate_iges, validate_step

STEP = """ISO-10303-21;
HEADER;
FILE_DESCRIPTION(('a (string) with ) and /* and END-ISO-10303-21;'),'2;1');
ENDSEC;
DATA;
/* a comment ( with ' an apostrophe */
#1 = CARTESIAN_POINT('it''s',(0.,0.,0.));
#2 = FOO(#1,((1,2),(3,4)));
ENDSEC;
END-ISO-10303-21;
"""


def step_file(tmp_path, text):
    p = tmp_path / "x.step"
    p.write_text(text)
    return p


def test_a_well_formed_step_file_passes_strings_and_comments_are_skipped(tmp_path):
    validate_step(step_file(tmp_path, STEP))
    validate_step(step_file(tmp_path, "\ufeff" + STEP + "\n\n"))


@pytest.mark.parametrize("edit, words", [
    (lambda t: t.replace("ISO-10303-21;\nHEADER", "HEADER", 1), "does not start"),
    (lambda t: t[:t.rindex("END-ISO")], "does not end"),
    (lambda t: t.replace("HEADER;", "HEAD;"), "no HEADER"),
    (lambda t: t.replace("ENDSEC;\nDATA;", "DATA;"), "HEADER section is not closed"),
    (lambda t: t.replace("ENDSEC;\nEND-ISO", "END-ISO"), "DATA section is not closed"),
    (lambda t: t.replace("'it''s'", "'it''s"), "unterminated"),
    (lambda t: t.replace("*/", ""), "unterminated"),
    (lambda t: t.replace("(3,4)));", "(3,4));"), "unclosed parentheses"),
    (lambda t: t.replace("#2 = FOO(#1,", "#2 = FOO(#1,))"), "without its"),
    (lambda t: t.replace("#2 = FOO(#1,", "#2 = FOO(#1," + "(" * (MAX_NESTING + 1) + ")" * (MAX_NESTING + 1) + ","),
     f"nested more than {MAX_NESTING}"),
])
def test_a_malformed_step_file_is_refused_naming_the_problem(tmp_path, edit, words):
    text = edit(STEP)
    assert text != STEP
    with pytest.raises(CagdError, match=words) as info:
        validate_step(step_file(tmp_path, text))
    assert str(info.value).startswith("path: STEP file ") and "x.step" in str(info.value)


def test_nesting_up_to_the_limit_passes(tmp_path):
    deep = "(" * (MAX_NESTING - 1) + ")" * (MAX_NESTING - 1)
    validate_step(step_file(tmp_path, STEP.replace("#2 = FOO(#1,", "#2 = FOO(#1," + deep + ",")))


def rec(text, letter, n):
    return f"{text:<72}{letter}{n:7d}"


def iges(entities, start="hand made", glob="1H,,1H;,,;"):
    """A minimal IGES file: entities are (type, parameter text) pairs."""
    S = [rec(start, "S", 1)]
    G = [rec(glob, "G", 1)]
    D, P = [], []
    for k, (etype, text) in enumerate(entities):
        seq = 2 * k + 1
        chunks = [text[i:i + 64] for i in range(0, len(text), 64)]
        D.append(rec(f"{etype:8d}{len(P) + 1:8d}{0:8d}{0:8d}{0:8d}{0:8d}{0:8d}{0:8d}{'00000000':>8}", "D", seq))
        D.append(rec(f"{etype:8d}{0:8d}{0:8d}{len(chunks):8d}{0:8d}", "D", seq + 1))
        P += [f"{c:<64}{seq:8d}P{len(P) + i + 1:7d}" for i, c in enumerate(chunks)]
    T = [rec(f"S{1:7d}G{1:7d}D{len(D):7d}P{len(P):7d}", "T", 1)]
    return "\n".join(S + G + D + P + T) + "\n"


LINE = (110, "110,0.,0.,0.,1.,2.,3.;")
CURVE = (126, "126,1,1,0,0,1,0,0.,0.,1.,1.,1.,1.,0.,0.,0.,1.,1.,1.,0.,1.,0.,0.,1.;")
NAME = (406, "406,1,5Hnamed;")


def iges_file(tmp_path, text):
    p = tmp_path / "x.igs"
    p.write_text(text)
    return p


def test_a_well_formed_iges_file_passes(tmp_path):
    validate_iges(iges_file(tmp_path, iges([LINE, CURVE, NAME])))
    validate_iges(iges_file(tmp_path, iges([LINE, CURVE]).replace("\n", "\r\n") + "\x1a"))


@pytest.mark.parametrize("edit, words", [
    (lambda t: t[:len(t) // 2], "columns"),
    (lambda t: "\n".join(ln for ln in t.splitlines() if ln[72] != "T") + "\n", "no T section"),
    (lambda t: "\n".join(ln for ln in t.splitlines() if ln[72] != "D") + "\n", "no D section"),
    (lambda t: t[:t.rindex("\n", 0, -1) + 1] + t[t.rindex("\n", 0, -1) + 1:].replace("D      6", "D      8"),
     "terminate record says 'D      8'"),
    (lambda t: t.replace("P      3", "P      4"), "sequence number"),
    (lambda t: t.replace("126,1,1,", "126,1H1,", 1), "holds numbers only"),
    (lambda t: t.replace("126,1,1,", "126,5,1,", 1), "needs"),
    (lambda t: t.replace("126,1,1,", "126,1,2,", 1), "degree"),
    (lambda t: t.replace("110,0.,0.", "110,0.,x.", 1), "not a number or a string"),
    (lambda t: t.replace("5Hnamed;", "9Hnamed;", 1), "string is not followed by a delimiter"),
    (lambda t: t.replace("5Hnamed;", "99Hnamed", 1), "string runs past"),
    (lambda t: t.replace("110,0.,0.,0.,1.,2.,3.;", "111,0.,0.,0.,1.,2.,3.;", 1), "not its entity type 110"),
    (lambda t: t.replace("3.;", "3.,", 1), "record delimiter"),
])
def test_a_malformed_iges_file_is_refused_naming_the_problem(tmp_path, edit, words):
    good = iges([LINE, CURVE, NAME])
    text = edit(good)
    assert text != good
    with pytest.raises(CagdError, match=words) as info:
        validate_iges(iges_file(tmp_path, text))
    assert str(info.value).startswith("path: IGES file ") and "x.igs" in str(info.value)


@pytest.mark.parametrize("old, new, words", [(b"P      3", b"P     \xb23", "sequence number"),
                                             (b"D      6P", b"D     \xb26P", "terminate record")])
def test_a_superscript_digit_is_not_a_number(tmp_path, old, new, words):
    """Found by the fuzz suite: byte 0xB2 reads as '\u00b2', which str.isdigit takes and
    int() refuses (a ValueError escaped)."""
    data = iges([LINE, CURVE, NAME]).encode()
    assert old in data
    path = tmp_path / "x.igs"
    path.write_bytes(data.replace(old, new, 1))
    with pytest.raises(CagdError, match=words):
        validate_iges(path)


@pytest.mark.parametrize("old, new, words", [
    ("126,1,1,0,0,1,0,0.,0.,1.,1.,", "126,1,1,0,0,1,0,0.,2.,1.,1.,", "knots decrease"),
    ("126,1,1,0,0,1,0,0.,0.,1.,1.,", "126,1,1,0,0,1,0,0.,0.,0.,0.,", "span no interval"),
    ("1.,1.,1.,1.,0.,0.,0.,", "1.,1.,1.,0.,0.,0.,0.,", "weight 2 .* weights are positive"),
    ("0.,0.,0.,1.,1.,1.,0.,1.", "0.,0.,0.,1.,1.E999,1.,0.,1.", "not a finite number"),
])
def test_b_spline_numbers_occt_dies_on_are_refused(tmp_path, old, new, words):
    """Decreasing knots (found by fuzzing a real file) killed OCCT's transfer."""
    etype, text = CURVE
    assert old in text
    with pytest.raises(CagdError, match=words):
        validate_iges(iges_file(tmp_path, iges([LINE, (etype, text.replace(old, new, 1)), NAME])))


def test_directory_pointers_and_sections_order(tmp_path):
    good = iges([LINE, CURVE])
    lines = good.splitlines()
    d1 = next(i for i, ln in enumerate(lines) if ln[72] == "D")
    bad = list(lines)
    bad[d1] = bad[d1][:8] + f"{9:8d}" + bad[d1][16:]                  # parameter pointer past the P section
    with pytest.raises(CagdError, match="parameter records P9"):
        validate_iges(iges_file(tmp_path, "\n".join(bad) + "\n"))
    bad = list(lines)
    bad[d1] = bad[d1][:48] + f"{7:8d}" + bad[d1][56:]                 # transformation matrix D7: no such entity
    with pytest.raises(CagdError, match="points at D7"):
        validate_iges(iges_file(tmp_path, "\n".join(bad) + "\n"))
    swapped = [lines[1], lines[0]] + lines[2:]
    with pytest.raises(CagdError, match="out of order"):
        validate_iges(iges_file(tmp_path, "\n".join(swapped) + "\n"))
    compressed = [ln[:72] + "C" + ln[73:] for ln in lines]
    with pytest.raises(CagdError, match="compressed or binary"):
        validate_iges(iges_file(tmp_path, "\n".join(compressed) + "\n"))


@pytest.mark.parametrize("name", ["ok", "with space", "é 中", "a;b,c", "it's", "x" * 255])
def test_check_name_accepts_printable_one_line_names(name):
    assert check_name(name) == name


@pytest.mark.parametrize("name, words", [(3, "must be a string"), ("", "non-empty"), (" a", "leading"),
                                         ("a\nb", "control"), ("a\x7fb", "control"), ("a\ud800", "surrogate"),
                                         ("x" * 256, "256 characters")])
def test_check_name_refuses(name, words):
    with pytest.raises(CagdError, match=words):
        check_name(name, "objects[0] name")


# --- the validators' own contract: any bytes give a verdict (pass or CagdError), nothing else ------------------
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

GOOD_IGES = iges([LINE, CURVE, NAME]).encode()
GOOD_STEP = STEP.encode()
EDITS = st.lists(st.tuples(st.floats(0.0, 1.0), st.sampled_from([b"", b",", b";", b"(", b")", b"'", b"H", b"1H",
                                                                 b"\n", b"\r", b"-", b"9", b"D", b"P", b"/*", b"\xff",
                                                                 b"\x00", b" " * 8])),
                 min_size=1, max_size=4)


def mutated(data: bytes, edits, cut: float) -> bytes:
    out = bytearray(data)
    for where, piece in edits:
        i = int(where * (len(out) - 1))
        out[i:i + 1] = piece
    return bytes(out[:max(1, int(cut * len(out)))])


@pytest.mark.parametrize("kind", ["IGES", "STEP"])
@settings(max_examples=300)
@given(edits=EDITS, cut=st.floats(0.5, 1.0))
def test_any_mutation_of_a_file_is_a_verdict(tmp_path_factory, kind, edits, cut):
    good, validate, suffix = (GOOD_IGES, validate_iges, "igs") if kind == "IGES" else (GOOD_STEP, validate_step, "step")
    p = tmp_path_factory.mktemp("fz") / f"x.{suffix}"
    p.write_bytes(mutated(good, edits, cut))
    try:
        validate(p)
    except CagdError as exc:
        assert str(exc).startswith(f"path: {kind} file ")

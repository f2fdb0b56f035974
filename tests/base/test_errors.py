"""ngincompat.errors: the error family, ParameterError naming a parameter, values quoted short."""

import pytest

from ngincompat.errors import (
    QUOTE,
    ConvergenceError,
    ExpressionError,
    Interrupted,
    InterruptedBeforeComputing,
    NgincompatError,
    ParameterError,
    require,
    shown,
)


def test_every_error_is_an_ngincompat_error_and_bad_input_a_value_error():
    """A caller catches the package's errors as one family, and bad input also as the
    ValueError it is."""
    for error in (ParameterError, ExpressionError, ConvergenceError, Interrupted,
                  InterruptedBeforeComputing):
        assert issubclass(error, NgincompatError)
    assert issubclass(ParameterError, ValueError) and issubclass(ExpressionError, ValueError)
    assert issubclass(ExpressionError, ParameterError)
    assert issubclass(InterruptedBeforeComputing, Interrupted)
    assert not issubclass(ConvergenceError, ValueError)


def test_require_passes_silently_and_otherwise_names_the_parameter_and_its_range():
    require(True, "maxh", 0.5, "> 0")
    with pytest.raises(ParameterError) as err:
        require(0.5 > 1, "maxh", -0.5, "> 0")
    assert str(err.value) == "maxh = -0.5 is out of range: allowed > 0"
    with pytest.raises(ParameterError, match=r"^footprint = 'star' is out of range: allowed "
                                             r"rectangle, circle$"):
        require(False, "footprint", "star", "rectangle, circle")


def test_the_message_is_one_line_whatever_the_value():
    with pytest.raises(ParameterError) as err:
        require(False, "name", "two\nlines", "a word")
    assert "\n" not in str(err.value) and "'two\\nlines'" in str(err.value)


def test_a_short_value_is_quoted_whole_as_its_repr():
    assert shown(0.25) == "0.25"
    assert shown("e1") == "'e1'"
    assert shown((1, 2)) == "(1, 2)"
    text = "x" * (QUOTE - 2)
    assert shown(text) == repr(text)


def test_a_long_string_is_cut_and_its_length_given():
    """A 5,000-character value is not echoed: its first characters and its length."""
    value = "a" * 5000
    got = shown(value)
    assert got == repr("a" * (QUOTE - 3)) + "... (5000 characters)"
    assert len(got) < QUOTE + 30


def test_another_long_value_is_cut_at_about_the_quote_length():
    value = list(range(1000))
    got = shown(value)
    assert got.startswith("[0, 1, 2, ") and got.endswith("...")
    assert len(got) == QUOTE
    with pytest.raises(ParameterError) as err:
        require(False, "points", value, "at most 3")
    assert len(str(err.value)) < 2 * QUOTE


def test_a_convergence_error_holds_the_history_and_the_last_converged_load():
    history = ["step 1", "step 2"]
    err = ConvergenceError("step below min_step", history=history, t_converged=0.5)
    assert str(err) == "step below min_step"
    assert err.history is history and err.t_converged == 0.5 and err.results is None
    bare = ConvergenceError("no equilibrium")
    assert bare.history is None and bare.t_converged is None


def test_an_interruption_holds_the_history_and_the_last_converged_load():
    err = InterruptedBeforeComputing("meshing", history=[], t_converged=0.0)
    assert isinstance(err, Interrupted)
    assert err.history == [] and err.t_converged == 0.0 and err.results is None

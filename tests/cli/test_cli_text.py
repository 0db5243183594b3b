"""What the command line says about itself: every command's --help opens with what it is for, and a misspelt
option, command or choice gets the closest known one."""

import pytest

from comparisons.cli.main import COMMANDS, build_parser, main


@pytest.mark.parametrize("command", COMMANDS)
def test_help_starts_with_what_the_command_is_for(command, capsys):
    with pytest.raises(SystemExit) as exit_:
        main([command, "--help"])
    assert exit_.value.code == 0
    text = capsys.readouterr().out
    first = text.splitlines()[0]
    assert not first.startswith("usage:") and first[:1].isupper(), first
    # the usage and the options follow the description, none of them lost
    assert f"usage: shimmy {command}" in text and "--help" in text


def test_verify_help_says_what_it_does(capsys):
    with pytest.raises(SystemExit):
        main(["verify", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert text.startswith("The main job:") and "report" in text.split("usage:")[0]


@pytest.mark.parametrize("argv, hint", [
    (["verify", "--quik"], "unrecognized arguments: --quik (did you mean '--quick'?)"),
    (["hopf", "--presure", "1.5"], "(did you mean '--pressure'?)"),
    (["hopf", "--vmaxx=30"], "unrecognized arguments: --vmaxx=30 (did you mean '--vmax'?)"),
    (["verfy"], "invalid choice: 'verfy'"),
    (["hopf", "--model", "mbz"], "(did you mean 'mbs'?)"),
])
def test_misspelt_options_commands_and_choices_get_the_closest(argv, hint, capsys):
    with pytest.raises(SystemExit) as exit_:
        main(argv)
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    assert hint in err and len(err.splitlines()) == 1, err
    if argv == ["verfy"]:
        assert err.rstrip().endswith("(did you mean 'verify'?)")


def test_nothing_close_gets_no_guess(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["cycles", "--zzzz"])
    assert exit_.value.code == 2
    assert capsys.readouterr().err == "shimmy: error: unrecognized arguments: --zzzz\n"


def test_every_command_is_offered():
    parser = build_parser()
    assert sorted(parser.commands) == sorted(COMMANDS)

"""Runs an obscura command line through the Python module instead: `cli_as_python.py INPUT -o OUT
--flag VALUE ...` calls obscura.process(INPUT, OUT, flag=VALUE, ...) with each flag spelled as
its keyword (--fov-deg -> fov_deg), so a test can give the CLI and Python the same settings."""
import ast
import sys

import obscura


def value(key, text):
    """A flag's text as the keyword's value: numbers as numbers, words and paths as they are."""
    if key == "camera_to_world":
        return [float(x) for x in text.split(",")]
    try:
        number = ast.literal_eval(text)
    except (ValueError, SyntaxError):
        return text
    return number if isinstance(number, (int, float)) else text


def main(args):
    source, out, keywords, i = args[0], None, {}, 1
    while i < len(args):
        flag = args[i]
        if flag == "-o":
            out, i = args[i + 1], i + 2
        elif flag == "--quiet":
            i += 1
        else:
            key = flag[2:].replace("-", "_")
            keywords[key], i = value(key, args[i + 1]), i + 2
    obscura.process(source, out, **keywords)


if __name__ == "__main__":
    main(sys.argv[1:])

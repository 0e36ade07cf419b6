"""Text helpers shared by the docs/results.md generators (make-results.sh's Python parts)."""


def wrap(text, indent=""):
    """A paragraph (indent "") or a Markdown list item's continuation (indent "  ") at 98."""
    lines, line = [], ""
    for w in text.replace(" %", "\u00a0%").split(" "):
        if line and len(line) + 1 + len(w) > 98:
            lines.append(line)
            line = indent + w
        else:
            line = w if not line else line + " " + w
    lines.append(line)
    return "\n".join(lines).replace("\u00a0", " ")

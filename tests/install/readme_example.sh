# Prints the fenced code block that follows "<!-- example: NAME -->" in a Markdown file, so tests
# run the README's examples exactly as written.
#   readme_example FILE NAME
readme_example() {
  awk -v marker="<!-- example: $2 -->" '
    $0 == marker { found = 1; next }
    found && /^```/ { if (inside) exit; inside = 1; next }
    inside { print }' "$1"
}

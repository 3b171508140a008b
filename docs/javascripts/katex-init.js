// KaTeX for pymdownx.arithmatex (generic mode): the \(...\) and \[...\] of each "arithmatex"
// element, rendered in the browser by the KaTeX bundled into the site (scripts/mkdocs_hooks.py
// copies it into site/javascripts/katex/): no network needed.
function renderMath() {
  for (const element of document.querySelectorAll(".arithmatex")) {
    renderMathInElement(element, {
      delimiters: [
        { left: "\\(", right: "\\)", display: false },
        { left: "\\[", right: "\\]", display: true },
      ],
      throwOnError: false,
    });
  }
}
if (typeof document$ !== "undefined") {
  document$.subscribe(renderMath); // Material's instant navigation
} else {
  document.addEventListener("DOMContentLoaded", renderMath);
}

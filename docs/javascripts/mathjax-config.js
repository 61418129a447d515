// MathJax 2 (Debian's libjs-mathjax) for the \( \) and \[ \] that pymdownx.arithmatex emits.
window.MathJax = {
  tex2jax: { inlineMath: [["\\(", "\\)"]], displayMath: [["\\[", "\\]"]],
             processEscapes: true, ignoreClass: ".*|", processClass: "arithmatex" },
  "HTML-CSS": { availableFonts: ["TeX"] },
};

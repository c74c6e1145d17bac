"""Generated code brought to life: loading generated modules, building the CPython
extension, running pdflatex.  The only layer that compiles or imports generated code."""

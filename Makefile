# Top-level entry points; the pipelines live in pipelines/Makefile.
.PHONY: paper law test clean-paper
paper law clean-paper:
	$(MAKE) -f pipelines/Makefile $@
test:
	cargo test --release

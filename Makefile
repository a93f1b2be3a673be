# Top-level entry points; the pipelines live in pipelines/Makefile.
.PHONY: paper test clean-paper
paper clean-paper:
	$(MAKE) -f pipelines/Makefile $@
test:
	cargo test --release

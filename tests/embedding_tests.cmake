# Tests of the embedding API (render/embedding.h): a host's raw GL scene with EmbeddedFabric drawn into it.
dtf_test(test_embedding SOURCES gl/embedding_test.cpp LIBS dtf_render dtf_io dtf_model)
dtf_test(test_embedding_alloc SOURCES gl/embedding_alloc_test.cpp LIBS dtf_render dtf_model)

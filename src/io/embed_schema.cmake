file(READ ${INPUT} SCHEMA_TEXT)
file(WRITE ${OUTPUT} "namespace bakesim {\nextern const char* const kSceneSchemaText;\nconst char* const kSceneSchemaText = R\"SCHEMA_JSON(${SCHEMA_TEXT})SCHEMA_JSON\";\n}\n")

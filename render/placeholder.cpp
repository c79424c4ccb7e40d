namespace dtf::render {}

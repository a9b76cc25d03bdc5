-- | The parser of MasterTool XE ST (catalogue §§ 1, 5-8). It never throws:
-- every problem is a 'VerificationError' with a stable kind, a position and
-- a message saying what was expected and what was found.
--
-- Syntax-error kinds: @expected-token@ (MT-VERR-4), @unexpected-after@
-- (MT-VERR-5), @unexpected@ (MT-VERR-6), @unsupported-type@,
-- @invalid-operand@, @nesting-too-deep@, and the lexical kinds of
-- "Stref.Lexical" (@invalid-char@, @invalid-symbol@, @comment-not-closed@).
module Stref.Syntax.Parser
  ( parseModule
  , parseExpression
  , parseStatements
  ) where

import Control.Monad (void, when)
import Control.Monad.Reader (asks, runReader)
import Data.Char (isDigit)
import qualified Data.List.NonEmpty as NE
import Data.Maybe (isJust)
import qualified Data.Set as Set
import Data.Text (Text)
import qualified Data.Text as T
import Stref.Lexical
import Stref.Policy (Policies)
import Stref.Syntax
import Stref.Verification
import Text.Megaparsec hiding (Pos)

-- | Parse a whole module. The policies matter for the lexical choices
-- (nested comments, ELSIF/ELSEIF). Errors carry the kinds of MT-VERR-1..6.
parseModule :: Policies -> FilePath -> Text -> Either VerificationError (Module Pos)
parseModule p file = runP p file (sc *> moduleP <* eof)

-- | One expression, alone in the text (for tests and tools).
parseExpression :: Policies -> Text -> Either VerificationError (Expr Pos)
parseExpression p = runP p "<expression>" (sc *> expr <* endOfInput)

-- | A list of statements, alone in the text (for tests and tools).
parseStatements :: Policies -> Text -> Either VerificationError [Stmt Pos]
parseStatements p = runP p "<statements>" (sc *> many statement <* endOfInput)

endOfInput :: Parser ()
endOfInput = eof <?> "the end of the text"

runP :: Policies -> FilePath -> Parser a -> Text -> Either VerificationError a
runP p file parser src =
  case runReader (runParserT' parser initial) (Env p 0) of
    (_, Right x) -> Right x
    (_, Left bundle) -> Left (toVerificationError p src (NE.head (bundleErrors bundle)))
  where
    initial =
      State
        { stateInput = src
        , stateOffset = 0
        , statePosState = PosState src 0 (initialPos file) (mkPos 1) ""
        , stateParseErrors = []
        }

------------------------------------------------------------------------------
-- Module structure (MT-POU-1, MT-POU-3, MT-POU-12)

moduleP :: Parser (Module Pos)
moduleP = do
  globals <- many globalBlock
  functions <- many functionP
  misplacedGlobal
  prog <- programP
  trailing
  pure (Module globals functions prog)
  where
    globalBlock = varBlockWith [SecVar]
    misplacedGlobal = do
      off <- getOffset
      w <- peekWord
      when (w `elem` map Just ["VAR", "VAR_INPUT", "VAR_IN_OUT", "VAR_OUTPUT"]) $
        failAt off "unexpected" (maybe "" id w <> " was not expected here: global variables are declared at the start of the module, before the functions") -- MT-POU-1
    trailing = do
      off <- getOffset
      atEnd <- isJust <$> optional (lookAhead eof)
      if atEnd
        then pure ()
        else do
          found <- describeAt off
          failAt off "unexpected" (found <> " was not expected after END_PROGRAM: a module ends with its one PROGRAM") -- MT-POU-1

functionP :: Parser (Function Pos)
functionP = do
  pos <- getPos
  keyword "FUNCTION"
  (_, n) <- name DeclName
  symbol ":"
  result <- basicTypeName
  blocks <- many (varBlockWith allSections)
  body <- many statement
  pouEnd "END_FUNCTION"
  pure (Function pos n result blocks body)

programP :: Parser (Program Pos)
programP = do
  pos <- getPos
  keyword "PROGRAM"
  (_, n) <- name DeclName
  blocks <- many (varBlockWith allSections)
  body <- many statement
  pouEnd "END_PROGRAM"
  pure (Program pos n blocks body)

allSections :: [VarSection]
allSections = [minBound .. maxBound]

-- | The end of a POU. A closing word of a statement that is not open here
-- (a stray @END_IF@) is reported as not expected (MT-VERR-6).
pouEnd :: Text -> Parser ()
pouEnd kw = keyword kw <|> stray
  where
    stray = do
      off <- getOffset
      w <- peekWord
      case w of
        Just u
          | u `elem` closers ->
              failAt off "unexpected" (u <> " was not expected here: no statement that it could close is open")
        _ -> empty
    closers = ["END_IF", "END_CASE", "END_WHILE", "END_FOR", "END_REPEAT", "ELSE", "ELSIF", "ELSEIF", "UNTIL", "THEN", "DO", "OF", "TO", "BY", "END_VAR", "END_FUNCTION", "END_PROGRAM"]

------------------------------------------------------------------------------
-- Declarations (MT-VAR-2..5, MT-ARR-1, MT-ARR-6, MT-MAP-4)

sectionKeyword :: VarSection -> Text
sectionKeyword = \case
  SecVar -> "VAR"
  SecInput -> "VAR_INPUT"
  SecInOut -> "VAR_IN_OUT"
  SecOutput -> "VAR_OUTPUT"

varBlockWith :: [VarSection] -> Parser (VarBlock Pos)
varBlockWith sections = do
  pos <- getPos
  sec <- choice [s <$ keyword (sectionKeyword s) | s <- sections]
  constant <- if sec == SecVar then option False (True <$ keyword "CONSTANT") else pure False
  decls <- many (varDecl sec)
  keyword "END_VAR"
  pure (VarBlock pos sec constant decls)

varDecl :: VarSection -> Parser (VarDecl Pos)
varDecl sec = do
  pos <- getPos
  names <- sepBy1 (name DeclName) (symbol ",")
  atOff <- getOffset
  at <- optional (keyword "AT" *> operandRef)
  when (isJust at) $ do
    when (length names > 1) $
      failAt atOff "unexpected" "AT was not expected after a list of names: AT maps exactly one variable" -- MT-MAP-4
    when (sec /= SecVar) $
      failAt atOff "unexpected" ("AT was not expected in " <> sectionKeyword sec <> ": only variables of VAR blocks can be mapped to PLC operands") -- MT-MAP-4(a)
  symbol ":"
  ty <- typeSpec
  ini <- optional (symbol ":=" *> initializer)
  symbol ";"
  pure (VarDecl pos names at ty ini)

typeSpec :: Parser (TypeSpec Pos)
typeSpec = arrayType <|> (TBasic <$> basicTypeName)
  where
    arrayType = do
      keyword "ARRAY"
      symbol "["
      lo <- expr
      symbol ".."
      hi <- expr
      symbol "]"
      keyword "OF"
      TArray lo hi <$> basicTypeName

initializer :: Parser (Initializer Pos)
initializer = listInit <|> (InitExpr <$> expr)
  where
    listInit = do
      pos <- getPos
      symbol "["
      xs <- sepBy1 expr (symbol ",")
      symbol "]"
      pure (InitList pos xs)

------------------------------------------------------------------------------
-- Statements (MT-STMT-1..23). Every statement ends with ';' (MT-STMT-23).

statement :: Parser (Stmt Pos)
statement = label "a statement" $ do
  -- dispatch on the first word instead of trying every statement in turn
  w <- peekWord
  case w of
    Just "IF" -> ifStmt
    Just "CASE" -> caseStmt
    Just "WHILE" -> whileStmt
    Just "REPEAT" -> repeatStmt
    Just "FOR" -> forStmt
    Just "EXIT" -> Exit <$> getPos <* keyword "EXIT" <* semi
    Just "RETURN" -> Return <$> getPos <* keyword "RETURN" <* semi
    Just _ -> assignOrCall
    Nothing -> Empty <$> getPos <* symbol ";"

semi :: Parser ()
semi = symbol ";"

-- | The statements of a nested block, one level deeper.
block :: Parser [Stmt Pos]
block = nested (many statement)

assignOrCall :: Parser (Stmt Pos)
assignOrCall = do
  pos <- getPos
  off <- getOffset
  (npos, n) <- name CallName
  s <-
    choice
      [ do
          symbol "["
          i <- nested expr
          symbol "]"
          symbol ":="
          Assign pos (LIndex npos n i) <$> expr
      , symbol ":=" *> (Assign pos (LVar npos n) <$> expr)
      , CallStmt pos n <$> arguments
      , strictElseif off n
      ]
  semi
  pure s
  where
    -- A1: under elsif-keyword=ELSIF the word ELSEIF is an ordinary name;
    -- say what happened instead of complaining about the next token
    strictElseif off n
      | T.toUpper (identText n) == "ELSEIF" =
          failAt off "expected-token" "expected ELSIF instead of ELSEIF (the elsif-keyword policy is ELSIF; ELSIF+ELSEIF accepts both)"
      | otherwise = empty

ifStmt :: Parser (Stmt Pos)
ifStmt = do
  pos <- getPos
  keyword "IF"
  first <- branch
  others <- many (elsif *> branch)
  els <- optional (keyword "ELSE" *> block)
  closing pos "IF" "END_IF"
  semi
  pure (If pos (first : others) els)
  where
    branch = do
      c <- expr
      keyword "THEN"
      (c,) <$> block
    -- A1: ELSEIF is a keyword only under the elsif-keyword policy
    elsif = keyword "ELSIF" <|> elseif
    elseif = do
      w <- peekWord
      if w == Just "ELSEIF" then keywordIfReserved "ELSEIF" else empty
    keywordIfReserved k = do
      reservedNow <- isReservedNow k
      if reservedNow then keyword k else empty

-- | The keyword that closes a statement opened at @at@. When it is missing
-- where a block ends (an END_ keyword, ELSE, ELSIF, UNTIL or the end of the
-- text), the error stays where the parser noticed it, as MT-VERR-4 has it
-- ("expected END_IF instead of END_WHILE"), and names the statement left
-- open; anything else found there is the ordinary "expected" error.
closing :: Pos -> Text -> Text -> Parser ()
closing at opener k = optional (keyword k) >>= maybe notClosed pure
  where
    notClosed = do
      off <- getOffset
      found <- lookAhead (optional (takeWhile1P Nothing isWordChar))
      done <- atEnd
      let word = T.toUpper <$> found
          endsABlock = done || maybe False (\w -> "END_" `T.isPrefixOf` w || w `elem` ["ELSE", "ELSIF", "ELSEIF", "UNTIL"]) word
      if endsABlock
        then failAt off "expected-token" ("expected " <> k <> " instead of " <> maybe "the end of the text" (\w -> "'" <> w <> "'") found <> ": the " <> opener <> " at line " <> T.pack (show (posLine at)) <> ", column " <> T.pack (show (posCol at)) <> " is not closed")
        else empty

isReservedNow :: Text -> Parser Bool
isReservedNow k = do
  p <- asks envPolicies
  pure (classifyWord p k == WKeyword)

caseStmt :: Parser (Stmt Pos)
caseStmt = do
  pos <- getPos
  keyword "CASE"
  sel <- expr
  keyword "OF"
  arms <- nested (some arm)
  els <- optional (keyword "ELSE" *> block)
  closing pos "CASE" "END_CASE"
  semi
  pure (Case pos sel arms els)
  where
    arm = do
      apos <- getPos
      labels <- caseLabels
      symbol ":"
      body <- nested (many (notFollowedBy (void (try (caseLabels *> symbol ":"))) *> statement))
      pure (CaseArm apos labels body)

-- | @1, 2, 5..10@; a value is a literal, a signed literal or a constant's
-- name (MT-STMT-8).
caseLabels :: Parser [CaseLabel Pos]
caseLabels = sepBy1 caseLabel (symbol ",")
  where
    caseLabel = do
      lo <- labelValue
      hi <- optional (symbol ".." *> labelValue)
      pure (maybe (LabelValue lo) (LabelRange lo) hi)
    labelValue =
      label "a case value" $
        choice
          [ do
              pos <- getPos
              symbol "-"
              EUnary pos Neg <$> literalExpr
          , literalExpr
          , uncurry EVar <$> name VarName
          ]

whileStmt :: Parser (Stmt Pos)
whileStmt = do
  pos <- getPos
  keyword "WHILE"
  c <- expr
  keyword "DO"
  body <- block
  closing pos "WHILE" "END_WHILE"
  semi
  pure (While pos c body)

repeatStmt :: Parser (Stmt Pos)
repeatStmt = do
  pos <- getPos
  keyword "REPEAT"
  body <- block
  closing pos "REPEAT" "UNTIL"
  c <- expr
  keyword "END_REPEAT" -- MT-STMT-14
  semi
  pure (Repeat pos body c)

forStmt :: Parser (Stmt Pos)
forStmt = do
  pos <- getPos
  keyword "FOR"
  v <- name DeclName
  symbol ":="
  start <- expr
  keyword "TO"
  end <- expr
  step <- optional (keyword "BY" *> expr)
  keyword "DO"
  body <- block
  closing pos "FOR" "END_FOR"
  semi
  pure (For pos v start end step body)

------------------------------------------------------------------------------
-- Expressions: Table 4-14 precedence, left associative (MT-OP-16, MT-OP-17)

expr :: Parser (Expr Pos)
expr = label "an expression" orLevel
  where
    orLevel = binaryLevel [Or] xorLevel
    xorLevel = binaryLevel [Xor] andLevel
    andLevel = binaryLevel [And] eqLevel -- AND and & (MT-OP-14)
    eqLevel = binaryLevel [Eq, Ne] cmpLevel
    cmpLevel = binaryLevel [Lt, Gt, Le, Ge] addLevel
    addLevel = binaryLevel [Add, Sub] mulLevel
    mulLevel = binaryLevel [Mul, Div, Mod] unary

-- | One precedence level, folded to the left: @10 - 4 - 3@ is @(10 - 4) - 3@.
-- The node's position is that of the operator. The operator is recognised
-- by looking at the input once, which keeps the seven levels cheap.
binaryLevel :: [BinOp] -> Parser (Expr Pos) -> Parser (Expr Pos)
binaryLevel ops next = next >>= rest
  where
    rest l = do
      input <- getInput
      case binaryOperatorAt input of
        Just (op, len) | op `elem` ops -> do
          pos <- getPos
          _ <- takeP Nothing len
          sc
          r <- nested next
          rest (EBinary pos op l r)
        _ -> label "an operator" empty <|> pure l

-- | The binary operator at the start of a text, and its length.
binaryOperatorAt :: Text -> Maybe (BinOp, Int)
binaryOperatorAt t = case T.unpack (T.take 2 t) of
  '<' : '=' : _ -> Just (Le, 2)
  '<' : '>' : _ -> Just (Ne, 2)
  '>' : '=' : _ -> Just (Ge, 2)
  '<' : _ -> Just (Lt, 1)
  '>' : _ -> Just (Gt, 1)
  '=' : _ -> Just (Eq, 1)
  '+' : _ -> Just (Add, 1)
  '-' : _ -> Just (Sub, 1)
  '*' : _ -> Just (Mul, 1)
  '/' : _ -> Just (Div, 1)
  '&' : _ -> Just (And, 1)
  c : _
    | isWordStart c ->
        let w = T.takeWhile isWordChar t
         in (,T.length w) <$> lookup (T.toUpper w) [("AND", And), ("OR", Or), ("XOR", Xor), ("MOD", Mod)]
  _ -> Nothing

unary :: Parser (Expr Pos)
unary = do
  pos <- getPos
  op <- optional ((Neg <$ symbol "-") <|> (Not <$ keyword "NOT"))
  case op of
    Just o -> EUnary pos o <$> nested unary
    Nothing -> primary

primary :: Parser (Expr Pos)
primary =
  choice
    [ symbol "(" *> nested expr <* symbol ")"
    , literalExpr
    , nameExpr
    ]

literalExpr :: Parser (Expr Pos)
literalExpr = do
  pos <- getPos
  ELit pos <$> (numberLiteral <|> boolLiteral)

nameExpr :: Parser (Expr Pos)
nameExpr = do
  (pos, n) <- name VarName
  choice
    [ ECall pos n <$> arguments -- MT-OP-18
    , do
        symbol "["
        i <- nested expr
        symbol "]"
        pure (EIndex pos n i)
    , pure (EVar pos n)
    ]

arguments :: Parser [Expr Pos]
arguments = do
  symbol "("
  args <- nested (sepBy expr (symbol ","))
  symbol ")"
  pure args

------------------------------------------------------------------------------
-- Error messages

toVerificationError :: Policies -> Text -> ParseError Text Issue -> VerificationError
toVerificationError policies src = \case
  FancyError off xs ->
    case [i | ErrorCustom i <- Set.toList xs] of
      (Issue kind msg at : _) -> VerificationError kind (posAt src at) msg
      [] ->
        VerificationError "unexpected" (posAt src off) $
          T.intercalate "; " [T.pack m | ErrorFail m <- Set.toList xs]
  TrivialError off _ expected ->
    let found = describeText src off
        labels = [renderItem i | i <- Set.toList expected]
        hasOperator = "an operator" `elem` labels
        rest = T.drop off src
        startsOperand = case T.uncons rest of
          Just (c, _)
            | isWordStart c -> classifyWord policies (T.toUpper (T.takeWhile isWordChar rest)) /= WKeyword
            | otherwise -> isDigit c || c == '('
          Nothing -> False
     in if hasOperator && startsOperand
          then
            VerificationError "unexpected-after" (posAt src off) $ -- MT-VERR-5
              found <> " was not expected after " <> previousToken src off <> " (an operator or the end of the expression was expected)"
          else
            VerificationError "expected-token" (posAt src off) $ -- MT-VERR-4
              "expected " <> orList (orderLabels labels) <> " instead of " <> found
  where
    renderItem = \case
      Label cs -> T.pack (NE.toList cs)
      Tokens cs -> "'" <> T.pack (NE.toList cs) <> "'"
      EndOfInput -> "the end of the file"

-- | Keywords and symbols first, descriptions ("a statement") last.
orderLabels :: [Text] -> [Text]
orderLabels ls = [l | l <- ls, not (descriptive l)] ++ [l | l <- ls, descriptive l]
  where
    descriptive l = any (`T.isPrefixOf` l) ["a ", "an ", "the "]

orList :: [Text] -> Text
orList = \case
  [] -> "something else"
  [x] -> x
  xs -> T.intercalate ", " (init xs) <> " or " <> last xs

-- | Line and column (1-based, a tab counts as one column) of an offset.
posAt :: Text -> Int -> Pos
posAt src off =
  let before = T.take off src
      l = 1 + T.count "\n" before
      col = 1 + T.length (T.takeWhileEnd (/= '\n') before)
   in Pos l col

-- | What stands at an offset, quoted, for "instead of ...".
describeText :: Text -> Int -> Text
describeText src off =
  let rest = T.drop off src
   in case T.uncons rest of
        Nothing -> "the end of the file"
        Just (c, r)
          | isWordStart c || isDigit c ->
              quote (T.cons c (T.takeWhile (\x -> isWordChar x || x == '#') r))
          | T.take 2 rest `elem` [":=", "<=", ">=", "<>", "..", "(*", "*)"] -> quote (T.take 2 rest)
          | otherwise -> quote (T.singleton c)
  where
    quote t = "'" <> t <> "'"

describeAt :: Int -> Parser Text
describeAt off = do
  st <- getParserState
  let ps = statePosState st
  pure (describeText (pstateInput ps) (off - pstateOffset ps))

-- | The token that ends just before an offset (white space skipped).
previousToken :: Text -> Int -> Text
previousToken src off =
  let before = T.dropWhileEnd (`elem` [' ', '\t', '\r', '\n']) (T.take off src)
      word = T.takeWhileEnd (\c -> isWordChar c || c == '#' || c == '.') before
   in "'" <> (if T.null word then T.takeEnd 1 before else word) <> "'"


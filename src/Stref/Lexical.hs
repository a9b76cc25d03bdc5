-- | The lexical elements of MasterTool XE ST (catalogue §1, MT-LEX-1..19) as
-- megaparsec building blocks for "Stref.Syntax.Parser".
--
-- There is no separate token stream: every token parser reads characters and
-- then skips the white space and comments after it ('lexeme'). Lexical errors
-- carry the kinds of Table 5-1: @invalid-char@ (MT-VERR-1), @invalid-symbol@
-- (MT-VERR-2) and @comment-not-closed@ (MT-VERR-3). They are raised after the
-- offending text has been consumed, so that no alternative swallows them.
module Stref.Lexical
  ( -- * The parser monad
    Parser
  , Env (..)
  , Issue (..)
  , failAt
  , getPos
  , nested
  , maxNesting
    -- * White space, comments, punctuation
  , sc
  , lexeme
  , symbol
  , keyword
  , isWordStart
  , isWordChar
  , peekWord
    -- * Names
  , WordClass (..)
  , classifyWord
  , NameUse (..)
  , name
  , isPlainName
    -- * Literals and operands
  , numberLiteral
  , boolLiteral
  , operandRef
  , basicTypeName
    -- * Word lists (MT-LEX-17)
  , keywords
  , unsupportedTypeNames
  , standardFunctionNames
  , predeclaredNames
  ) where

import Control.Monad (void, when)
import Control.Monad.Reader (Reader, asks, local)
import Data.Char (isAsciiLower, isAsciiUpper, isDigit, isHexDigit, ord, toUpper)
import Data.Maybe (isJust)
import Data.Ratio ((%))
import qualified Data.Set as Set
import Data.Text (Text)
import qualified Data.Text as T
import Stref.Policy (ElsifKeyword (..), NestedComments (..), Policies (..))
import Stref.Syntax
import Stref.Types (BasicType, parseTypeName)
import Text.Megaparsec hiding (Pos)
import Text.Megaparsec.Char (char, string)

-- | A lexical or syntax problem with its stable kind.
data Issue = Issue {issueKind :: Text, issueMessage :: Text, issueOffset :: Int}
  deriving (Eq, Ord, Show)

instance ShowErrorComponent Issue where
  showErrorComponent = T.unpack . issueMessage

-- | What the parser needs to know while it reads: the policies (comment
-- nesting, ELSIF spelling) and how deeply it is nested.
data Env = Env {envPolicies :: Policies, envDepth :: Int}

type Parser = ParsecT Issue Text (Reader Env)

-- | Fail with a stable kind, reporting the given offset (usually the start
-- of the offending token). Megaparsec sees the error at the current offset,
-- so that it wins over the errors of alternatives that stopped earlier.
failAt :: Int -> Text -> Text -> Parser a
failAt off kind msg = do
  here <- getOffset
  parseError (FancyError (max off here) (Set.singleton (ErrorCustom (Issue kind msg off))))

getPos :: Parser Pos
getPos = do
  SourcePos _ l c <- getSourcePos
  pure (Pos (unPos l) (unPos c))

-- | Deeper nesting than this (parentheses, operators, statements) is refused
-- with @nesting-too-deep@ rather than risking the stack.
maxNesting :: Int
maxNesting = 200

-- | Run a parser one nesting level deeper. Call it after consuming the token
-- that opens the level, so that the error is not lost by an alternative.
nested :: Parser a -> Parser a
nested p = do
  d <- asks envDepth
  if d >= maxNesting
    then do
      off <- getOffset
      failAt off "nesting-too-deep" ("the program is nested more than " <> tshow maxNesting <> " levels deep (parentheses, operators or statements); split it into simpler parts")
    else local (\e -> e {envDepth = d + 1}) p

------------------------------------------------------------------------------
-- White space and comments (MT-LEX-7, MT-LEX-8)

-- | White space: space, tab and line breaks (MT-LEX-7), and the byte-order
-- mark that editors on Windows put at the start of a file.
isBlank :: Char -> Bool
isBlank c = c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\xFEFF'

-- | Characters that may start or continue a token outside comments.
legalChar :: Char -> Bool
legalChar c = isWordChar c || c `elem` (":;,()[].+-*/<>=&%#" :: String)

isWordStart :: Char -> Bool
isWordStart c = isAsciiUpper c || isAsciiLower c || c == '_'

isWordChar :: Char -> Bool
isWordChar c = isWordStart c || isDigit c

-- | Skip white space and comments, then make sure the next character can
-- start a token (MT-VERR-1).
sc :: Parser ()
sc = do
  hidden (skipMany (void (takeWhile1P Nothing isBlank) <|> comment))
  off <- getOffset
  next <- optional (lookAhead anySingle)
  case next of
    -- MT-LEX-11: '#' can only follow a base (2#, 8#, 16#); alone it starts nothing
    Just '#' -> failAt off "invalid-char" "the character '#' is not part of the language here: it can only follow the base of a number (2#, 8# or 16#)"
    -- a comment of the IEC dialects: say so, rather than that '/' is unexpected
    Just '/' -> do
      two <- lookAhead (optional (try (string "//")))
      when (isJust two) $ failAt off "invalid-char" "MasterTool XE has no // comments: write (* ... *) (--dialect tecomat and nexto accept //)"
    Just c
      | not (legalChar c) ->
          failAt off "invalid-char" ("the character " <> describeChar c <> " is not part of the language") -- MT-LEX-15
    _ -> pure ()

describeChar :: Char -> Text
describeChar c
  | c < ' ' || c == '\DEL' = "with code " <> tshow (ord c)
  | otherwise = "'" <> T.singleton c <> "'"

-- | @(* ... *)@. Without nesting the first @*)@ closes the comment (MT-LEX-8);
-- with the @nested-comments@ policy each @(*@ needs its own @*)@.
comment :: Parser ()
comment = do
  off <- getOffset
  _ <- string "(*"
  nesting <- asks (pNestedComments . envPolicies)
  let loop, loopStep :: Int -> Parser ()
      loop d = do
        _ <- takeWhileP Nothing (\c -> c /= '*' && c /= '(')
        finished <- atEnd
        if finished
          then failAt off "comment-not-closed" "this comment is not closed with *) before the end of the file" -- MT-VERR-3
          else loopStep d
      loopStep d =
        choice
          [ string "*)" >> (if d <= 1 then pure () else loop (d - 1))
          , if nesting == Nesting then string "(*" >> loop (d + 1) else empty
          , anySingle >> loop d
          ]
  loop 1

lexeme :: Parser a -> Parser a
lexeme p = p <* sc

-- | A punctuation symbol; @:@ does not match the start of @:=@, @<@ not that
-- of @<=@ or @<>@, and so on.
symbol :: Text -> Parser ()
symbol s = label ("'" <> T.unpack s <> "'") $ do
  here <- hidden (optional (try (lookAhead (string s <* notFollowedBy (satisfy continues)))))
  case here of
    Just _ -> string s >> sc
    Nothing -> empty
  where
    continues c = case s of
      ":" -> c == '='
      "<" -> c == '=' || c == '>'
      ">" -> c == '='
      "." -> c == '.'
      _ -> False

-- | A word: letters, digits and @_@ starting with a letter or @_@.
rawWord :: Parser Text
rawWord = do
  c <- satisfy isWordStart
  rest <- takeWhileP Nothing isWordChar
  pure (T.cons c rest)

-- | The next word, upper-cased, without consuming it.
peekWord :: Parser (Maybe Text)
peekWord = optional (lookAhead (T.toUpper <$> rawWord))

-- | A keyword, case-insensitive (MT-LEX-5).
keyword :: Text -> Parser ()
keyword k = label (T.unpack k) $ do
  w <- lookAhead rawWord
  if T.toUpper w == k then rawWord >> sc else empty

------------------------------------------------------------------------------
-- Reserved words (MT-LEX-17)

-- | Words that are never names. The PT list of the manual's appendix, less
-- the type names, the standard function names and the predeclared signals
-- (listed separately below). The printed typos VAR_ACESS and "RESOURCE ON
-- END_REPEAT" are read as VAR_ACCESS (both spellings reserved) and
-- END_RESOURCE. Two deliberate omissions: the SFC action
-- qualifiers N R S L D P SD DS SL LD ST (the manual's own IF example declares
-- a variable D), and END (decision A30). ELSEIF is added by policy (A1).
keywords :: Set.Set Text
keywords =
  Set.fromList
    [ "AT", "ARRAY", "OF", "CASE", "ELSE", "END_CASE", "EXIT", "FALSE", "TRUE"
    , "FOR", "TO", "BY", "DO", "END_FOR", "FUNCTION", "END_FUNCTION", "IF", "THEN"
    , "ELSIF", "END_IF", "REPEAT", "UNTIL", "END_REPEAT", "RETURN", "CONSTANT"
    , "VAR", "END_VAR", "VAR_INPUT", "WHILE", "END_WHILE", "AND", "OR", "XOR"
    , "NOT", "MOD", "EN", "ENO", "F_EDGE", "R_EDGE", "FUNCTION_BLOCK"
    , "END_FUNCTION_BLOCK", "PROGRAM", "WITH", "END_PROGRAM", "READ_ONLY"
    , "READ_WRITE", "RESOURCE", "ON", "END_RESOURCE", "RETAIN", "STRUCT", "END_STRUCT", "TASK"
    , "TYPE", "END_TYPE", "VAR_IN_OUT", "VAR_OUTPUT", "VAR_EXTERNAL", "VAR_ACESS"
    , "VAR_ACCESS", "JMP", "CAL", "RET", "ACTION", "END_ACTION", "INITIAL_STEP"
    , "END_STEP", "STEP", "TRANSITION", "FROM", "END_TRANSITION"
    , "BOOL", "BYTE", "WORD", "DWORD", "USINT", "INT", "DINT", "REAL"
    ]

-- | Reserved type names that MasterTool XE does not implement.
unsupportedTypeNames :: Set.Set Text
unsupportedTypeNames =
  Set.fromList
    [ "SINT", "UINT", "UDINT", "LINT", "ULINT", "LWORD", "LREAL", "TIME", "DATE"
    , "TIME_OF_DAY", "TOD", "DATE_AND_TIME", "DT", "STRING", "ANY", "ANY_NUM"
    , "ANY_REAL", "ANY_INT", "ANY_BIT", "ANY_DATE"
    ]

-- | The standard function blocks of the IEC dialects, named in a
-- MasterTool XE declaration.
standardFBNames :: Set.Set Text
standardFBNames = Set.fromList ["TON", "TOF", "TP", "CTU", "CTD", "CTUD", "R_TRIG", "F_TRIG", "SR", "RS"]

-- | Reserved names of standard functions. They may be called (the checker
-- then reports that the function is not declared, MT-OP-21) but not declared
-- or used as variables. EXPT is the one that exists (MT-OP-20). The list
-- prints MIN as "MIM"; both are reserved here.
standardFunctionNames :: Set.Set Text
standardFunctionNames =
  Set.fromList
    [ "ABS", "SQRT", "LN", "LOG", "EXP", "SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN"
    , "SEL", "MAX", "MIN", "MIM", "LIMIT", "MUX", "LEFT", "RIGHT", "MID", "CONCAT"
    , "INSERT", "DELETE", "REPLACE", "LEN", "FIND", "ADD", "MUL", "DIV", "EXPT", "MOVE"
    , "SHL", "SHR", "ROR", "ROL", "GT", "GE", "EQ", "LE", "LT", "NE", "TRUNC"
    ]

-- | Reserved names that denote predeclared variables: the module signals
-- (MT-SIG-1) and INTERNAL_OVERFLOW (MT-OP-7).
predeclaredNames :: Set.Set Text
predeclaredNames = Set.fromList ["INPUT1", "INPUT2", "INPUT3", "OUTPUT1", "OUTPUT2", "OUTPUT3", "INTERNAL_OVERFLOW"]

data WordClass
  = WKeyword
  | WUnsupportedType
  | WStandardFunction
  | WPredeclared
  | WInternal -- ^ @INTERNAL_*@ other than INTERNAL_OVERFLOW
  | WPlain
  deriving (Eq, Show)

-- | The class of an upper-cased word. Conversion names (@INT_TO_REAL@,
-- @ANY_TO_DINT@) are plain names: they are functions the checker knows.
classifyWord :: Policies -> Text -> WordClass
classifyWord p u
  | u `Set.member` keywords = WKeyword
  | u == "ELSEIF" && pElsifKeyword p == ElsifAndElseif = WKeyword -- A1
  | u `Set.member` unsupportedTypeNames = WUnsupportedType
  | u `Set.member` standardFunctionNames = WStandardFunction
  | u `Set.member` predeclaredNames = WPredeclared
  | "INTERNAL_" `T.isPrefixOf` u = WInternal
  | otherwise = WPlain

-- | A name the user may declare under the given policies (used by the
-- generator of syntax trees).
isPlainName :: Policies -> Text -> Bool
isPlainName p t = validIdent t && classifyWord p (T.toUpper t) == WPlain

validIdent :: Text -> Bool
validIdent t = case T.uncons t of
  Just (c, rest) -> isWordStart c && T.all isWordChar rest && not ("__" `T.isInfixOf` t) && T.last t /= '_'
  Nothing -> False

------------------------------------------------------------------------------
-- Names (MT-LEX-3)

-- | Where a name is read: a declaration, a variable in code, a called
-- function.
data NameUse = DeclName | VarName | CallName
  deriving (Eq, Show)

-- | A name. Keywords fail without consuming (the caller's expectation then
-- shows in the message); a reserved word in the wrong place and a malformed
-- identifier (MT-VERR-2) are reported after consuming the word.
name :: NameUse -> Parser (Pos, Ident)
name use = label "a name" $ do
  pos <- getPos
  off <- getOffset
  -- a malformed number where a name is expected is an invalid symbol
  _ <- hidden (optional (lookAhead (satisfy isDigit) *> lookAhead numberLiteral))
  policies <- asks envPolicies
  w <- try (lookAhead rawWord >>= \w -> if classifyWord policies (T.toUpper w) == WKeyword then empty else pure w)
  _ <- rawWord
  let u = T.toUpper w
  -- MT-LEX-3, MT-LEX-15: two '_' in a row, or a final '_'
  when ("__" `T.isInfixOf` w) $
    failAt off "invalid-symbol" ("'" <> w <> "' is not a valid identifier: it contains two '_' in a row")
  when (T.last w == '_') $
    failAt off "invalid-symbol" ("'" <> w <> "' is not a valid identifier: it ends with '_'")
  sc
  callFollows <- isJust <$> hidden (optional (lookAhead (char '(')))
  let reserved what = failAt off "unexpected" (w <> " is " <> what <> " and cannot be used as a name here")
  case (classifyWord policies u, use) of
    (WKeyword, _) -> reserved "a reserved word"
    (WUnsupportedType, _) -> reserved "a reserved type name"
    (WInternal, _) -> reserved "reserved (names starting with INTERNAL_ belong to the controller)"
    (WStandardFunction, DeclName) -> reserved "the reserved name of a standard function"
    (WStandardFunction, _) | not callFollows -> reserved "the reserved name of a standard function"
    (WPredeclared, DeclName) -> reserved "a predeclared variable"
    _ -> pure ()
  pure (pos, Ident w)

------------------------------------------------------------------------------
-- Literals (MT-LEX-9..16)

-- | A run of digits with separators: no @__@ and no final @_@ (MT-LEX-9).
checkSeparators :: Int -> Text -> Text -> Parser ()
checkSeparators off whole digits = do
  when ("__" `T.isInfixOf` digits) $
    failAt off "invalid-symbol" ("'" <> whole <> "' is not a valid number: it contains two '_' in a row")
  when (T.isPrefixOf "_" digits) $
    failAt off "invalid-symbol" ("'" <> whole <> "' is not a valid number: its digits start with '_'")
  when (T.isSuffixOf "_" digits) $
    failAt off "invalid-symbol" ("'" <> whole <> "' is not a valid number: it ends with '_'")

-- | An integer (decimal or @2#@, @8#@, @16#@) or a real literal. A sign is
-- not part of the literal (MT-LEX-19).
numberLiteral :: Parser Literal
numberLiteral = label "a number" $ do
  off <- getOffset
  _ <- lookAhead (satisfy isDigit)
  ds <- takeWhile1P Nothing (\c -> isDigit c || c == '_')
  -- the real test needs a digit after the point: '1..10' is a range (MT-LEX-13)
  isReal <- isJust <$> hidden (optional (try (lookAhead (char '.' >> satisfy isDigit))))
  lit <-
    if isReal
      then realRest off ds
      else do
            based <- optional (char '#')
            case based of
              Just _ -> basedRest off ds
              Nothing -> do
                whole <- wordAt off
                checkSeparators off whole ds
                pure (LInt (readDigits 10 ds) 10)
  -- a number glued to a letter, '_' or a second '#' or '.' is one bad symbol
  bad <- hidden (optional (lookAhead (satisfy (\c -> isWordChar c || c == '#'))))
  when (isJust bad) $ do
    whole <- wordAt off
    failAt off "invalid-symbol" ("'" <> whole <> "' is not a valid number")
  secondPoint <- hidden (optional (try (lookAhead (char '.' >> satisfy isDigit))))
  when (isJust secondPoint) $ do
    whole <- wordAt off
    failAt off "invalid-symbol" ("'" <> whole <> "' is not a valid number: it has a second '.'") -- MT-LEX-14
  sc
  pure lit
  where
    realRest off ds = do
      _ <- char '.'
      frac <- takeWhileP Nothing (\c -> isDigit c || c == '_')
      hasExp <- optional (satisfy (\c -> c == 'e' || c == 'E'))
      (sign, ex) <- case hasExp of
        Nothing -> pure (1, "0")
        Just _ -> do
          sgn <- option 1 ((1 <$ char '+') <|> ((-1) <$ char '-'))
          ex <- takeWhileP Nothing (\c -> isDigit c || c == '_')
          when (T.null ex) $ do
            whole <- wordAt off
            failAt off "invalid-symbol" ("'" <> whole <> "' is not a valid real number: the exponent has no value") -- MT-LEX-15
          pure (sgn, ex)
      whole <- wordAt off
      checkSeparators off whole ds
      checkSeparators off whole frac
      checkSeparators off whole ex
      let e = sign * readDigits 10 ex
      when (abs e > 4000) $
        failAt off "invalid-symbol" ("'" <> whole <> "' is not a valid real number: the exponent is far too large")
      let mantissa = readDigits 10 (ds <> frac)
          scale = toInteger (T.length (T.filter (/= '_') frac))
          value = (mantissa % 1) * (10 ^^ (e - scale))
      pure (LReal value)
    basedRest off ds = do
      digits <- takeWhileP Nothing isWordChar
      whole <- wordAt off
      base <- case T.filter (/= '_') ds of
        b | ds == b, b `elem` ["2", "8", "16"] -> pure (readDigits 10 b)
        _ -> failAt off "invalid-symbol" ("'" <> whole <> "' is not a valid number: the base must be 2, 8 or 16") -- MT-LEX-10
      when (T.null digits) $
        failAt off "invalid-symbol" ("'" <> whole <> "' is not a valid number: there are no digits after '#'")
      checkSeparators off whole digits
      case T.find (\c -> c /= '_' && not (digitIn base c)) digits of
        Just c -> failAt off "invalid-symbol" ("'" <> whole <> "' is not a valid number: '" <> T.singleton c <> "' is not a digit of base " <> tshow base) -- MT-LEX-11
        Nothing -> pure ()
      pure (LInt (readDigits base digits) (fromInteger base))

digitIn :: Integer -> Char -> Bool
digitIn base c = case base of
  2 -> c == '0' || c == '1'
  8 -> c >= '0' && c <= '7'
  16 -> isHexDigit c
  _ -> isDigit c

readDigits :: Integer -> Text -> Integer
readDigits base = go . T.filter (/= '_')
  where
    -- halves, so that a literal of a million digits is read in about
    -- n log n time instead of n^2 (one multiplication per digit)
    go t
      | T.length t <= 64 = T.foldl' step 0 t
      | otherwise =
          let (hi, lo) = T.splitAt (T.length t `div` 2) t
           in go hi * base ^ T.length lo + go lo
    step acc c
      | c == '_' = acc
      | isDigit c = acc * base + toInteger (ord c - ord '0')
      | otherwise = acc * base + toInteger (ord (toUpper c) - ord 'A' + 10)

-- | The symbol starting at an offset, for messages: the longest run of
-- characters that may belong to a number or a name, '#', '.', and a sign
-- right after an exponent letter.
wordAt :: Int -> Parser Text
wordAt off = do
  st <- getParserState
  let ps = statePosState st
      rest = T.drop (off - pstateOffset ps) (pstateInput ps)
  pure (T.take 60 (grab rest))
  where
    grab t = case T.uncons t of
      Nothing -> ""
      Just (c, r)
        | isWordChar c || c == '#' -> T.cons c (grab' c r)
        | otherwise -> T.singleton c
    grab' prev t = case T.uncons t of
      Just (c, r)
        | isWordChar c || c == '#' -> T.cons c (grab' c r)
        | c == '.', Just (d, _) <- T.uncons r, isDigit d -> T.cons c (grab' c r)
        | (c == '+' || c == '-'), prev == 'e' || prev == 'E' -> T.cons c (grab' c r)
      _ -> ""

boolLiteral :: Parser Literal
boolLiteral = (LBool True <$ keyword "TRUE") <|> (LBool False <$ keyword "FALSE") -- MT-LEX-16

------------------------------------------------------------------------------
-- PLC operands after AT (MT-MAP-5..7)

-- | @%M0123@, @%M0006.6@, @%TM010[15]@, @%TM0010[ 0 ]@. Any letters are kept
-- (even @%D@): the checker decides which operands exist (MT-VERR-39).
operandRef :: Parser (Pos, OperandRef)
operandRef = label "a PLC operand such as %M0010" $ do
  pos <- getPos
  off <- getOffset
  _ <- char '%'
  letters <- takeWhileP Nothing (\c -> isAsciiUpper c || isAsciiLower c)
  address <- takeWhileP Nothing isDigit
  when (T.null letters || T.null address) $ do
    whole <- wordAt (off + 1)
    failAt off "invalid-operand" ("'%" <> whole <> "' is not a PLC operand; write it like %M0010, %M0006.6 or %TM0010[0]")
  sub <-
    choice
      [ BitOf . readDigits 10 <$> (char '.' *> takeWhile1P (Just "a bit number") isDigit)
      , Position . readDigits 10 <$> (char '[' *> sc *> lexeme (takeWhile1P (Just "a table position") isDigit) <* char ']')
      , pure NoSub
      ]
  -- a bit of a table position (%TM0010[2].1) cannot be written in ST
  bitAfterPosition <- hidden (optional (lookAhead (char '.')))
  case (sub, bitAfterPosition) of
    (Position _, Just _) -> do
      whole <- wordAt (off + 1)
      failAt off "invalid-operand" ("'%" <> whole <> "...' is not a PLC operand: a table position has no bits")
    _ -> pure ()
  sc
  pure (pos, OperandRef (T.toUpper letters) (readDigits 10 address) sub)

-- | One of the eight basic types (MT-TYPE-1). The other reserved type names
-- get their own message.
basicTypeName :: Parser BasicType
basicTypeName = label "a type (BOOL, BYTE, WORD, DWORD, USINT, INT, DINT or REAL)" $ do
  off <- getOffset
  w <- lookAhead rawWord
  case parseTypeName w of
    Just t -> rawWord >> sc >> pure t
    Nothing
      | T.toUpper w `Set.member` unsupportedTypeNames -> do
          _ <- rawWord
          failAt off "unsupported-type" ("the type " <> T.toUpper w <> " is not supported by MasterTool XE; the types are BOOL, BYTE, WORD, DWORD, USINT, INT, DINT and REAL (--dialect tecomat and nexto have " <> T.toUpper w <> ")")
      | T.toUpper w `Set.member` standardFBNames -> do
          _ <- rawWord
          failAt off "unsupported-type" (T.toUpper w <> " is a standard function block of IEC 61131-3; MasterTool XE has no function blocks (--dialect tecomat and nexto have them)")
      | otherwise -> empty

tshow :: Show x => x -> Text
tshow = T.pack . show
